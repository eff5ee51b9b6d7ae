#!/usr/bin/env python3
"""The whole mesh of a .qsp file, polygons section (0x05) and comments section (0x81) included,
written from format-spec/qsp_format.md alone ("Grid layout", "Polygons section", "Comments section",
"Decoding a mesh") without reading the codec's C++, on top of qsplayout.py (topology, layout) and
qspgeo.py (container, range coder, geometry).

usage: qsppoly.py FILE.qsp [--obj MESH.obj] [--reference PREFIX]
       decodes FILE to its output mesh (vertices, faces with their corners, float bits) and its comment
       lines. --obj: compares them with MESH.obj, the mesh the file was made from: the same faces with
       the same corner cycles on the same vertices up to renumbering and face order, every position bit
       for bit (skipped for a quantized file), and, when the file has a comments section, its lines
       with MESH.obj's leading comment block. --reference: compares them exactly (vertex order, face
       order, each face's first corner, float bits) with the reference decoder's output that
       dump_stencils wrote to PREFIX.mesh and PREFIX.comments. Exit 0 if all agree, else 1.
"""
import struct
import sys

import qspgeo as g
import qsplayout as lay

need = g.need
NONE = g.NONE


# ---------------- "Grid layout": the quads of the layout, component after component ----------------
def grid_quads(c):
    """Annulus (kind 2) and torus (kind 3): cell (x, y) as (x, y), (x+1, y), (x+1, y+1), (x, y+1),
    x + 1 taken modulo a; a torus's row b is row 0 shifted back by the twist (the lattice
    {(a, 0), (twist, b)}: (x, b) is (x - twist, 0))."""
    a, b = c.a, c.b
    if c.kind == 2:
        at = lambda x, y: y * a + x % a
        V = a * (b + 1)
    else:
        at = lambda x, y: (y * a + x % a) if y < b else (x + c.twist) % a
        V = a * b
    quads = [(at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)) for y in range(b) for x in range(a)]
    return V, quads


def layout(topology, C, U):
    """(vertex count, quads) of the grid layout: components offset by those before them, then U
    unreferenced vertices."""
    base = 0
    quads = []
    for c in lay.decode_topology(topology, C):
        if c.kind >= 2:
            n, qs = grid_quads(c)
        else:
            lay.layout_schematic(c)
            n, qs = c.V, c.quads
        quads += [tuple(base + v for v in q) for q in qs]
        base += n
    return base + U, quads


# ---------------- "Polygons section": holes ----------------
def hole_loops(V, quads):
    """The layout's boundary loops: (loops, where) with loops[l] the vertices along loop l and
    where[v] = (l, position) of each hole vertex. nxt[v], prv[v] along the loops."""
    half = set()
    for q in quads:
        for k in range(4):
            half.add((q[k], q[(k + 1) % 4]))
    ext_out = {}                        # v -> w: the exterior half-edge out of v (quad w -> v on the boundary)
    for (u, w) in half:
        if (w, u) not in half:
            need(w not in ext_out, 'two exterior half-edges out of one vertex')
            ext_out[w] = u
    loops, where = [], {}
    for v in range(V):
        if v in ext_out and v not in where:
            loop = []
            x = v
            while x not in where:
                where[x] = (len(loops), len(loop))
                loop.append(x)
                x = ext_out[x]
            need(x == v, 'an exterior walk that does not come back')
            loops.append(loop)
    nxt = ext_out
    prv = {w: u for u, w in ext_out.items()}
    return loops, where, nxt, prv


class HalfEdge:
    __slots__ = ('u', 'w', 'closed')

    def __init__(self, u, w):
        self.u, self.w, self.closed = u, w, False


class Stacks:
    """Open half-edges into and out of each ref, newest on top; a closed one leaves (lazily)."""

    def __init__(self):
        self.into, self.outof = {}, {}

    def push(self, e):
        self.outof.setdefault(e.u, []).append(e)
        self.into.setdefault(e.w, []).append(e)

    @staticmethod
    def _top(stacks, v):
        s = stacks.get(v)
        while s and s[-1].closed:
            s.pop()
        return s[-1] if s else None

    def in_(self, v):
        return self._top(self.into, v)

    def out(self, v):
        return self._top(self.outof, v)


# ---------------- "Polygons section": the section ----------------
SYMBOLS = ('follow', 'close', 'new', 'boundary', 'interior')
STATS = {}  # what a decode used: how much of the text the files exercise


def seen(what):
    STATS[what] = STATS.get(what, 0) + 1


def decode_polygons(payload, V, quads, limit_faces=None):
    """The polygons section against a layout of V vertices and these quads: (I, glue groups, region
    faces as lists of refs, interior positions payload)."""
    pos = 0
    I, pos = g.read_varint(payload, pos)
    R, pos = g.read_varint(payload, pos)
    G, pos = g.read_varint(payload, pos)
    L, pos = g.read_varint(payload, pos)
    need(V + I < 1 << 31, 'more refs than 2^31 - 1')
    for what, x in (('interior', I), ('regions', R), ('groups', G)):
        need(x <= 2048 * (L + 8), '%s count past what the stream can hold' % what)
    need(2 * G <= V + I, 'more glue groups than refs can make')
    need(L <= len(payload) - pos, 'stream longer than the section')
    stream = payload[pos:pos + L]
    rest = payload[pos + L:]
    rd = g.RangeDecoder(stream)
    T = {}

    def m(name, key=0):
        if name not in T:
            T[name] = g.Table()
        return T[name][key]

    def t(name):
        if name not in T:
            T[name] = g.Table()
        return T[name]

    def bit(name, key=0):
        return rd.bit(m(name, key))

    def integer(name):
        return rd.integer(t(name))

    refs = V + I
    # Glue
    groups = []
    prev_first = None
    for gi in range(G):
        size = integer('glue_size') + 2
        gap = integer('glue_gap')
        first = gap if gi == 0 else prev_first + gap + 1
        need(first < refs, 'glue ref past V + I')
        members = [first]
        for _ in range(size - 1):
            x = members[-1] + integer('glue_step') + 1
            need(x < refs, 'glue ref past V + I')
            members.append(x)
        groups.append(members)
        prev_first = first
    cls = {}
    for grp in groups:
        for r in grp:
            need(r not in cls, 'a ref in two glue groups')
            cls[r] = grp[0]
    klass = lambda r: cls.get(r, r)
    quad_refs = {v for q in quads for v in q}
    for grp in groups:
        for r in grp:
            need(r >= V or r in quad_refs, 'glue names a layout vertex in no quad')

    loops, where, nxt, prv = hole_loops(V, quads)
    faces = []
    created = 0                       # interior refs created so far (all regions)
    prev_loop, prev_position = 0, 0   # the previous edge start
    free_seen = False
    for r in range(R):
        stacks = Stacks()
        for v in where:                # the quads' hole half-edges next(v) -> v, open again for each region
            stacks.push(HalfEdge(nxt[v], v))
        mine = []                      # interior refs this region created
        gates = []
        h = [None]                     # the last hole vertex this region listed

        def new_ref():
            nonlocal created
            x = V + created
            created += 1
            need(created <= I, 'more interior refs than I')
            mine.append(x)
            return x

        def listed(x):
            if x < V and x in where:
                h[0] = x

        if bit('start_free'):
            free_seen = True
            seen('free start')
            first = [new_ref()]
            gate = None
        else:
            need(not free_seen, 'an edge start after a free start')
            dl = integer('start_loop')
            seen('edge start, same loop' if dl == 0 else 'edge start, other loop')
            if dl == 0:
                loop, position = prev_loop, prev_position + integer('start_step')
            else:
                loop, position = prev_loop + dl, integer('start_position')
            need(loop < len(loops) and position < len(loops[loop]), 'edge start past the holes')
            prev_loop, prev_position = loop, position
            u = loops[loop][position]
            gate = stacks.in_(u)
            need(gate is not None and gate.u == nxt[u], 'edge start on a closed hole edge')
            first = None
        prev_kind = 0
        while True:
            if gate is not None:
                need(not gate.closed, 'a gate another face closed')
                gate.closed = True
                corners = [gate.w, gate.u]
            else:
                corners = first
            if rd.bit(m('triangle', prev_kind)):
                d = 3
            else:
                d = rd.integer(t('big%d' % prev_kind)) + 5
            need(d <= V + I, 'face degree past V + I')
            for x in corners:
                listed(x)
            s = 5
            while len(corners) < d:
                last = int(len(corners) == d - 1)
                ctx = 6 * last + s
                if bit('corner', (ctx, 0)):
                    sym = 0
                elif bit('corner', (ctx, 1)):
                    sym = 1
                elif bit('corner', (ctx, 2)):
                    sym = 2
                else:
                    sym = 3 + bit('corner', (ctx, 3))
                if sym == 0:
                    e = stacks.in_(corners[-1])
                    need(e is not None, 'follow without a half-edge into the previous corner')
                    x = e.u
                elif sym == 1:
                    e = stacks.out(corners[0])
                    need(e is not None, 'close without a half-edge out of the first corner')
                    x = e.w
                elif sym == 2:
                    x = new_ref()
                elif sym == 3:
                    if bit('same_loop'):
                        seen('same_loop')
                        need(h[0] is not None, 'same_loop before any hole vertex')
                        l, p0 = where[h[0]]
                        b = integer('hole_step')
                        need(b < len(loops[l]), 'hole_step past the loop')
                        x = loops[l][(p0 + b) % len(loops[l])]
                    else:
                        l = integer('hole_loop')
                        b = integer('hole_position')
                        need(l < len(loops) and b < len(loops[l]), 'hole vertex past the holes')
                        x = loops[l][b]
                else:
                    k = integer('interior_back')
                    need(k < len(mine), 'interior_back past the region\'s interior refs')
                    x = mine[-1 - k]
                seen(SYMBOLS[sym])
                need(x not in corners, 'a corner repeating a ref of the face')
                corners.append(x)
                listed(x)
                s = sym
            faces.append(corners)
            need(limit_faces is None or len(quads) + len(faces) <= limit_faces, 'too many faces')
            # its edges
            start = 1 if gate is not None else 0
            edges = [(i, corners[i], corners[(i + 1) % d]) for i in range(start, d)]
            closes = []
            for i, u, w in edges:
                e = stacks.in_(u)
                if e is not None and klass(e.u) == klass(w):
                    closes.append(e)
                    continue
                e = stacks.out(w)
                if e is not None and klass(e.w) == klass(u):
                    closes.append(e)
                    continue
                closes.append(None)
            for e in closes:
                if e is not None:
                    seen('closed by an edge')
                    e.closed = True
            for (i, u, w), e in zip(edges, closes):
                if e is not None:
                    continue
                he = HalfEdge(u, w)
                stacks.push(he)
                if rd.bit(m('open', min(i, 2) + 3 * (d == 3))):
                    seen('gate')
                    gates.append(he)
            prev_kind = 1 if d == 3 else 2
            if not gates:
                break
            gate = gates.pop()
    need(created == I, 'interior refs created %d, I = %d' % (created, I))
    rd.finish()
    return I, groups, faces, rest


def interior_positions(rest, N):
    """"Interior positions": N positions as float bits, a chain of stencils in layout order."""
    if N == 0:
        need(len(rest) == 0, 'bytes after the stream with no interior position to hold')
        return []
    need(len(rest) >= 1 and rest[0] & g.LAYOUT_ORDER, 'interior positions not in layout order')
    need(N <= 2048 * (len(rest) + 8), 'more interior positions than the bytes can hold')
    st = []
    for k in range(N):
        s = lay.blank()
        if k:
            s['w'] = k - 1
        st.append(s)
    fb, _ = g.decode_geometry(rest, N, st)
    return [(fb[0][k], fb[1][k], fb[2][k]) for k in range(N)]


# ---------------- "Comments section" ----------------
def comments(payload):
    n, pos = g.read_varint(payload, 0)
    need(1 <= n <= len(payload) - pos, 'comment line count %d' % n)
    out = []
    for _ in range(n):
        ln, pos = g.read_varint(payload, pos)
        need(ln <= len(payload) - pos, 'comment line past the section')
        text = payload[pos:pos + ln]
        need(b'\n' not in text and b'\r' not in text, 'comment line with CR or LF')
        out.append(text)
        pos += ln
    need(pos == len(payload), 'bytes after the last comment line')
    return out


# ---------------- "Decoding a mesh" ----------------
def decode_file(data):
    """(positions as float bits per output vertex, faces, comment lines, quantized?)."""
    secs = g.sections(data)
    V, F, C, U = g.counts(secs[1])
    n, quads = layout(secs[2], C, U)
    need(n == V and len(quads) == F, 'counts disagree with the topology')
    geo = secs[3]
    coding, st = lay.stencils(secs[2], C, U, bool(geo[0] & g.LAYOUT_ORDER))
    fb, _ = g.decode_geometry(geo, V, st)
    pos = [None] * V
    for k in range(V):
        pos[coding[k]] = (fb[0][k], fb[1][k], fb[2][k])
    lines = comments(secs[0x81]) if 0x81 in secs else []
    if 0x05 not in secs:
        return pos, [list(q) for q in quads], lines, geo[1] != 0
    need(data[9] >= 1, 'a polygons section in a 3.0 file')
    I, groups, faces, rest = decode_polygons(secs[0x05], V, quads)
    first_of = {}
    for grp in groups:
        for r in grp:
            first_of[r] = grp[0]
    out_index = {}
    for r in range(V + I):
        if first_of.get(r, r) == r:
            out_index[r] = len(out_index)
    N = sum(1 for r in range(V, V + I) if first_of.get(r, r) == r)
    ipos = interior_positions(rest, N)
    out_pos = [None] * len(out_index)
    ip = iter(ipos)                 # the interior refs that are their vertex's smallest ref, in ref order
    for r in range(V + I):
        if r in out_index:
            out_pos[out_index[r]] = pos[r] if r < V else next(ip)
    out_faces = []
    for f in [list(q) for q in quads] + faces:
        o = [out_index[first_of.get(r, r)] for r in f]
        need(len(set(o)) == len(o), 'a face repeating an output vertex')
        out_faces.append(o)
    return out_pos, out_faces, lines, geo[1] != 0


# ---------------- comparisons ----------------
def f32(x):
    return struct.unpack('<I', struct.pack('<f', float(x)))[0]


def read_obj(path):
    """Positions (float32 bits), faces (0-based) and the leading comment block (qsp_format.md
    "Comments section": the text after '#' of each comment line up to the first line that is
    neither blank nor a comment)."""
    pos, faces, lead = [], [], []
    leading = True
    for raw in open(path, 'rb').read().split(b'\n'):
        line = raw[:-1] if raw.endswith(b'\r') else raw
        s = line.strip()
        if leading:
            if s.startswith(b'#'):
                lead.append(line[line.index(b'#') + 1:])
                continue
            if not s:
                continue
            leading = False
        w = s.split()
        if not w or w[0].startswith(b'#'):
            continue
        if w[0] == b'v':
            pos.append(tuple(f32(float(x)) for x in w[1:4]))
        elif w[0] == b'f':
            idx = [int(x.split(b'/')[0]) for x in w[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
    return pos, faces, lead


def canon_face(f):
    k = f.index(min(f))
    return tuple(f[k:] + f[:k])


def compare_obj(path, mesh, obj_path):
    pos, faces, lines, quantized = mesh
    opos, ofaces, olead = read_obj(obj_path)
    bad = []
    if len(pos) != len(opos) or len(faces) != len(ofaces):
        return ['%d vertices and %d faces, the .obj %d and %d' % (len(pos), len(faces), len(opos), len(ofaces))]
    if not quantized:
        by_pos = {}
        for i, p in enumerate(opos):
            need(p not in by_pos, '%s: two vertices at one position: cannot match by position' % obj_path)
            by_pos[p] = i
        to = []
        for i, p in enumerate(pos):
            if p not in by_pos:
                bad.append('vertex %d at %s is no vertex of the .obj' % (i, [hex(x) for x in p]))
                to.append(None)
            else:
                to.append(by_pos[p])
        if not bad:
            mine = sorted(canon_face([to[v] for v in f]) for f in faces)
            theirs = sorted(canon_face(f) for f in ofaces)
            if mine != theirs:
                diff = sorted(set(mine) ^ set(theirs))
                bad.append('faces differ from the .obj (first: %s)' % (diff[:4],))
    if lines and lines != olead:
        bad.append('comment lines %r, the .obj\'s leading block %r' % (lines, olead))
    if not lines and olead and '_comments' in path:
        bad.append('no comments section, the .obj has a leading block')
    return bad


def compare_reference(mesh, prefix):
    """Exactly the reference decoder's output (dump_stencils' PREFIX.mesh, PREFIX.comments; no
    PREFIX.mesh for a file with an order section, which this decoder does not read)."""
    import os
    pos, faces, lines, _ = mesh
    bad = []
    rlines = [bytes.fromhex(x[1:]) for x in open(prefix + '.comments').read().split()]  # 'x' + hex each
    if rlines != lines:
        bad.append('comment lines %r, the reference decoder\'s %r' % (lines, rlines))
    if not os.path.exists(prefix + '.mesh'):
        return bad
    words = open(prefix + '.mesh').read().split()
    nv, nf = int(words[0]), int(words[1])
    k = 2
    rpos = []
    for _ in range(nv):
        rpos.append(tuple(int(x, 16) for x in words[k:k + 3]))
        k += 3
    rfaces = []
    for _ in range(nf):
        d = int(words[k])
        rfaces.append([int(x) for x in words[k + 1:k + 1 + d]])
        k += 1 + d
    if rpos != pos:
        bad.append('positions differ from the reference decoder\'s (first at %s)' %
                   next((i for i in range(min(len(pos), len(rpos))) if pos[i] != rpos[i]), 'the count'))
    if rfaces != faces:
        bad.append('faces differ from the reference decoder\'s (first at %s: %s, reference %s)' %
                   next(((i, faces[i], rfaces[i]) for i in range(min(len(faces), len(rfaces)))
                         if faces[i] != rfaces[i]), ('the count', len(faces), len(rfaces))))
    return bad


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith('-'):
        print(__doc__, file=sys.stderr)
        return 2
    path = args[0]
    opts = dict(zip(args[1::2], args[2::2]))
    try:
        mesh = decode_file(open(path, 'rb').read())
    except g.FormatError as e:
        print('%s: refused: %s' % (path, e))
        return 1
    bad = []
    if '--obj' in opts:
        bad += compare_obj(path, mesh, opts['--obj'])
    if '--reference' in opts:
        bad += compare_reference(mesh, opts['--reference'])
    for b in bad:
        print('%s: %s' % (path, b))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
