#!/usr/bin/env python3
"""Helpers for bench_match.sh (standard library only).

  match_graphs.py shuffle IN.obj OUT.obj SEED   random vertex renumbering, face order and first corners
  match_graphs.py dimacs  IN.obj OUT.dimacs     the vertex-edge graph in DIMACS ("p edge V E", "e u v")

Only `v` and `f` lines are read (v/vt/vn face syntax and negative indices allowed); everything else
in the OBJ is ignored. The shuffled OBJ holds positions (as written in IN) and faces only.
"""
import random
import sys


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(line.split()[1:4])
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                faces.append(idx)
    return verts, faces


def shuffle(src, dst, seed):
    verts, faces = read_obj(src)
    rng = random.Random(seed)
    order = list(range(len(verts)))  # new -> old
    rng.shuffle(order)
    new_of = [0] * len(verts)
    for new, old in enumerate(order):
        new_of[old] = new
    rng.shuffle(faces)
    with open(dst, "w") as out:
        out.write("".join("v %s %s %s\n" % tuple(verts[old]) for old in order))
        lines = []
        for face in faces:
            r = rng.randrange(len(face))
            face = face[r:] + face[:r]
            lines.append("f " + " ".join(str(new_of[v] + 1) for v in face) + "\n")
        out.write("".join(lines))


def dimacs(src, dst):
    verts, faces = read_obj(src)
    edges = set()
    for face in faces:
        for k in range(len(face)):
            u, v = face[k], face[(k + 1) % len(face)]
            edges.add((u, v) if u < v else (v, u))
    with open(dst, "w") as out:
        out.write("p edge %d %d\n" % (len(verts), len(edges)))
        out.write("".join("e %d %d\n" % (u + 1, v + 1) for u, v in sorted(edges)))


if __name__ == "__main__":
    if len(sys.argv) == 5 and sys.argv[1] == "shuffle":
        shuffle(sys.argv[2], sys.argv[3], int(sys.argv[4]))
    elif len(sys.argv) == 4 and sys.argv[1] == "dimacs":
        dimacs(sys.argv[2], sys.argv[3])
    else:
        sys.exit(__doc__)
