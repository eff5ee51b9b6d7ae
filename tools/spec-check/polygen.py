#!/usr/bin/env python3
"""polygen.py OUT.obj SEED: a polygon mesh for check.sh, so that qsppoly.py meets every symbol and
rule of qsp_format.md's polygons section: a jittered 7x7 grid whose cells are quads, holes, two
triangles, a fan round an interior vertex, a triangle beside a quad with an interior corner, or a
hexagon over two cells; a fin on an interior edge (three faces on one edge); two quads of opposite
orientations; and free regions: an octahedron, a triangulated torus and a dodecahedron (pentagons, so
that corners follow corners of every symbol). Positions are distinct, so qsppoly.py can match them."""
import math
import random
import sys

out, seed = sys.argv[1], int(sys.argv[2])
random.seed(seed)
V, F = [], []


def v(x, y, z):
    V.append((x, y, z))
    return len(V)


n = 7
g = {(i, j): v(i, j, round(random.uniform(-0.2, 0.2), 3)) for j in range(n + 1) for i in range(n + 1)}
merged = set()
for j in range(n):
    for i in range(n):
        if (i, j) in merged:
            continue
        a, b, c, d = g[i, j], g[i + 1, j], g[i + 1, j + 1], g[i, j + 1]
        r = random.random()
        if r < 0.45:
            F.append([a, b, c, d])
        elif r < 0.6:
            F += [[a, b, c], [a, c, d]]
        elif r < 0.7:
            m = v(i + 0.5, j + 0.5, round(random.uniform(0.1, 0.3), 3))
            F += [[a, b, m], [b, c, m], [c, d, m], [d, a, m]]
        elif r < 0.8 and i + 1 < n:
            merged.add((i + 1, j))
            F.append([a, b, g[i + 2, j], g[i + 2, j + 1], c, d])
        elif r < 0.88:
            m = v(i + 0.5, j + 0.25, round(random.uniform(0.1, 0.3), 3))
            F += [[a, b, m], [b, c, d, m], [m, d, a]]
        # else a hole
F.append([g[3, 3], g[4, 3], v(3.5, 3, 1.5)])  # a fin: the edge has three faces
k = [v(20, 0, 0), v(21, 0, 0), v(21, 1, 0), v(20, 1, 0), v(22, 0, 0), v(22, 1, 0)]
F += [[k[0], k[1], k[2], k[3]], [k[1], k[2], k[5], k[4]]]  # opposite orientations
o = [v(30, 0, 0), v(32, 0, 0), v(31, 1, 0), v(31, -1, 0), v(31, 0, 1), v(31, 0, -1)]
for t in [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]:
    F.append([o[x] for x in t])
R0, r0, na, nb = 3, 1, 7, 5
tv = {}
for i in range(na):
    for j in range(nb):
        u, w = 2 * math.pi * i / na, 2 * math.pi * j / nb
        tv[i, j] = v(round(40 + (R0 + r0 * math.cos(w)) * math.cos(u), 4),
                     round((R0 + r0 * math.cos(w)) * math.sin(u), 4), round(r0 * math.sin(w), 4))
for i in range(na):
    for j in range(nb):
        a, b, c, d = tv[i, j], tv[(i + 1) % na, j], tv[(i + 1) % na, (j + 1) % nb], tv[i, (j + 1) % nb]
        F += [[a, b, c], [a, c, d]] if random.random() < 0.5 else [[a, b, d], [b, c, d]]
# the dodecahedron, as the dual of an icosahedron
ph = (1 + 5 ** 0.5) / 2
iv = [(-1, ph, 0), (1, ph, 0), (-1, -ph, 0), (1, -ph, 0), (0, -1, ph), (0, 1, ph), (0, -1, -ph), (0, 1, -ph),
      (ph, 0, -1), (ph, 0, 1), (-ph, 0, -1), (-ph, 0, 1)]
itri = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
        (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
        (8, 6, 7), (9, 8, 1)]
dv = [v(*(round(60 * (a == 0) + sum(iv[x][a] for x in t) / 3, 4) for a in range(3))) for t in itri]
for p in range(12):
    around = {}
    for fi, t in enumerate(itri):
        if p in t:
            q = t.index(p)
            around[t[(q + 1) % 3]] = (fi, t[(q + 2) % 3])
    start = x = next(iter(around))
    face = []
    while True:
        fi, x = around[x]
        face.append(dv[fi])
        if x == start:
            break
    F.append(face[::-1])
with open(out, 'w') as w:
    for p in V:
        w.write('v %g %g %g\n' % p)
    for f in F:
        w.write('f %s\n' % ' '.join(map(str, f)))
