#!/usr/bin/env python3
"""The whole mesh of a .qsp file, polygons section (0x05), texture coordinates section (0x06), face
labels section (0x07), subdivision tags section (0x08), normals section (0x09), colours section (0x0b,
qspcolors.py), interior positions section (0x0c), exact values section (0x0d, qspvalues.py), properties section
(0x0e, qspprops.py), symmetry section (0x0f, qspmirror.py), order section (0x04), comments section
(0x81) and coded comments section (0x85) included, written from format-spec/qsp_format.md alone ("Grid
layout", "Order section", "Polygons section", "Texture coordinates section", "Face labels section",
"Subdivision tags section", "Normals section", "Interior positions section", "Symmetry section",
"Comments section", "Coded comments section", "Decoding a mesh") without reading the
codec's C++, on top of qsplayout.py (topology, layout) and qspgeo.py (container, range coder,
geometry).

usage: qsppoly.py FILE.qsp [--obj MESH.obj] [--reference PREFIX] [--tex-obj MESH.obj [--exact]]
                  [--labels-obj MESH.obj [--exact]] [--labels-decompressed OUT.obj]
                  [--tags-obj MESH.obj [--exact]] [--tags-decompressed OUT.obj]
                  [--normals-obj MESH.obj [--exact]] [--normals-decompressed OUT.obj]
                  [--values-obj MESH [--exact]] [--values-decompressed OUT]
                  [--decompressed OUT.obj] [--stats]
       decodes FILE to its output mesh (vertices, faces with their corners, float bits, each corner's
       texture coordinate and normal, in the original order when the file has an order section), its
       face labels and material libraries, its subdivision tags, and its comment lines. --obj:
       compares them with MESH.obj, the mesh the file was made from: the same faces with the same
       corner cycles on the same vertices up to renumbering and face order (as cycles of corner
       positions when two of MESH.obj's vertices share a position), every position bit for bit
       (skipped for a quantized file), and, when the file has a comments section, its lines with
       MESH.obj's leading comment block.
       --reference: compares them exactly (vertex order, face order, each face's first corner, float
       bits) with the reference decoder's output that dump_stencils wrote to PREFIX.mesh and
       PREFIX.comments. --tex-obj: compares every corner's position and texture coordinate (float32
       bits; rounded to the binary grid a component's mode names, as --quantize-uv rounds them) with
       MESH.obj's up to renumbering, face order and rotation, and the texture coordinates no corner
       names; with --exact index for index (a file written with --keep-order). --decompressed:
       compares positions, faces and texture coordinates index for index with OUT.obj, what `qsp
       decompress FILE` wrote. --labels-obj: compares each face's object, groups, material and
       smoothing group (the last o, g, usemtl, s statement before it in MESH.obj, none before the
       first) with its corners' positions as a multiset of faces up to rotation (face by face with
       --exact), the names no face takes and the mtllib lines; --labels-decompressed: the same,
       face by face, with OUT.obj, what `qsp decompress FILE` wrote (OBJ_UNLABELLED_FIRST: faces
       with more kinds unlabelled first).
       --tags-obj: compares the tags, tag for tag, with MESH.obj's `t` lines: names, strings, floats
       by value (a binary32 one with the text read as binary32), integers; crease and corner ones as
       the vertices' positions, hole ones as the faces' corner positions (index for index with
       --exact). --tags-decompressed: the same, index for index, with OUT.obj.
       --normals-obj: compares every corner's position and normal (float32 bits, the third field of
       `f v/vt/vn`) with MESH.obj's up to renumbering, face order and rotation, and the normals no
       corner names; with --exact index for index. --normals-decompressed: the same, index for index,
       with OUT.obj.
       --values-obj: compares the texture coordinates, normals, vertex and face colours as binary64
       values (the exact values section's, else the value of each binary32's shortest text) with the
       values MESH's texts denote (MESH: .obj, .off or .ply; index for index with --exact, else as
       multisets and corner by corner), and the section byte for byte with the one the text's encoder
       choices give (qspvalues.py). --values-decompressed: the same values, index for index, with the
       texts `qsp decompress FILE` wrote to OUT (each read as binary64, and no longer in significant
       digits than the shortest text).
       --stats: prints how often each rule of the text was met. Exit 0 if all agree, else 1.
"""
import math
import struct
import subprocess
import sys

import qspgeo as g
import qsplayout as lay
import qspexact
import qspcolors
import qspvalues
import qspprops
import qspmirror

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


_seen = seen


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
    need(not rest[0] & 0x20, 'the interior positions use mirror prediction (tools bit 5)')
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


# ---------------- "Coded comments section" ----------------
def coded_comments(payload):
    """The lines of a coded comments section (0x85): a text length, then one range-coded stream of
    the text's bytes (the lines joined by LF), each as 8 logistic decisions of a text model."""
    size, pos = g.read_varint(payload, 0)
    stream = payload[pos:]
    need(size <= 1 << 20, 'coded comments text length %d past 2^20' % size)
    need(size <= 1024 * (len(stream) + 8), 'coded comments text length %d past the stream' % size)
    lfs = 0
    dec = g.RangeDecoder(stream)
    order0 = g.Table()
    order1 = g.Table()
    order2 = g.Table()
    order3 = g.Table()
    match = g.Table()
    weights = {}
    text = bytearray()
    latest = {}           # 4 bytes -> the position just after their latest occurrence
    ptr, length = 0, 0    # the match: the expected byte's position, the agreeing length (0: none)

    def index(key):        # the top 16 bits of key * 0x9E3779B1 mod 2^32
        return ((key * 0x9E3779B1) % (1 << 32)) >> 16

    for i in range(size):
        def prev(k):
            return text[i - k] if i >= k else 0
        c1 = prev(1)
        c12 = c1 + 256 * prev(2)
        c123 = c12 + 65536 * prev(3)
        node = 1
        for b in range(7, -1, -1):
            M1 = order1[256 * c1 + node]
            M2 = order2[index(256 * c12 + node)]
            M3 = order3[index(256 * c123 + node)]
            speaks = False
            if length > 0:
                e = text[ptr]
                speaks = (e + 256) >> (b + 1) == node
            M0 = match[(e >> b) & 1, length] if speaks else order0[node]
            k = 2 * ((M1.seen > 0) + (M2.seen > 0) + (M3.seen > 0)) + (1 if speaks else 0)
            W = weights.setdefault(k, [32768, 32768, 32768, 32768, 0])
            bit = dec.logistic([M0, M1, M2, M3], W, rate=10)
            node = 2 * node + bit
        c = node - 256
        need(c != 0x0D, 'coded comments byte %d is a CR' % i)
        lfs += c == 0x0A
        need(lfs < 1 << 16, 'coded comments byte %d begins line %d, past 2^16' % (i, lfs + 1))
        text.append(c)
        n = i + 1
        if length > 0 and text[ptr] == c:
            length, ptr = min(length + 1, 15), ptr + 1
        else:
            length = 0
        if n >= 4:
            key = bytes(text[n - 4:n])
            if key in latest and length == 0:
                ptr = latest[key]
                while length < 15 and length < ptr and text[ptr - 1 - length] == text[n - 1 - length]:
                    length += 1
            latest[key] = n
    dec.finish()
    return bytes(text).split(b'\n')


# ---------------- "Face labels section" ----------------
LABEL_KINDS = (b'o', b'g', b'usemtl', b's')   # kinds 0..3: objects, groups, materials, smoothing groups


def decode_labels(payload, F, minor=9):
    """The face labels section over F output faces (before an order section) of a 3.`minor` file:
    (labels, names, libraries) with labels[k][f] face f's name index of kind k or None, names[k] kind
    k's names 0 .. N-1 (both only for the kinds present) and libraries the mtllib texts in order."""
    need(len(payload) >= 1, 'empty face labels section')
    kinds = payload[0]
    need(kinds >> 6 == 0, 'reserved face labels kinds bits set (0x%02x)' % kinds)
    need(kinds & 0x1f != 0, 'face labels: no kind and no library (0x%02x)' % kinds)
    front = bool(kinds & 32)     # "front-coded texts (from 3.9)"
    need(not front or minor >= 9, 'front-coded names are format 3.9\'s, and the file says it is 3.%d' % minor)
    if front:
        seen('labels: front-coded')
    pos = 1
    total = 0

    def text(before):
        nonlocal pos, total
        shared = 0
        if front:
            shared, pos = g.read_varint(payload, pos)
            need(shared <= len(before), 'face label text shares %d bytes with a shorter one' % shared)
            if shared:
                seen('labels: a shared prefix')
        ln, pos = g.read_varint(payload, pos)
        need(ln <= len(payload) - pos, 'face label name or library past the section')
        t = payload[pos:pos + ln]
        need(b'\n' not in t and b'\r' not in t, 'face label name or library with CR or LF')
        pos += ln
        total += shared + ln
        need(total <= 64 * len(payload), 'face label texts past 64 times the section')
        return before[:shared] + t

    def texts(n):
        out = []
        for _ in range(n):
            out.append(text(out[-1] if out else b''))
        return out

    present = [k for k in range(4) if kinds >> k & 1]
    names = {}
    for k in present:   # (each kind's names follow its count)
        N, pos = g.read_varint(payload, pos)
        need(N <= len(payload) - pos, 'kind %d: %d names past the section' % (k, N))
        names[k] = texts(N)
        need(len(set(names[k])) == N, 'kind %d: two equal names' % k)
        seen('labels: kind %d' % k)
    libraries = []
    if kinds & 16:
        L, pos = g.read_varint(payload, pos)
        need(1 <= L <= len(payload) - pos, 'material library count %d' % L)
        libraries = texts(L)
        seen('labels: libraries')
    rd = g.RangeDecoder(payload[pos:])
    labels = {}
    for k in present:
        T, earlier = g.Table(), g.Table()    # fresh models per kind
        N = len(names[k])
        m = 0
        out = []
        p, c = None, 0
        for f in range(F):
            if rd.bit(T['same', c]):
                x, c = p, 1
                seen('labels: same')
            else:
                c = 0
                if rd.bit(T['is_new']):
                    need(m < N, 'kind %d: face %d takes a new name past the %d names' % (k, f, N))
                    x = m
                    m += 1
                    seen('labels: new')
                elif p is not None and rd.bit(T['is_none']):
                    x = None
                    seen('labels: none')
                else:
                    R = m - 1 if p is not None else m
                    r = rd.integer(earlier)
                    need(r < R, 'kind %d: face %d takes earlier name %d of %d' % (k, f, r, R))
                    x = r if p is None or r < p else r + 1   # names 0 .. m-1 without p
                    seen('labels: earlier')
            out.append(x)
            p = x
        if m < N:
            seen('labels: names no face takes')
        labels[k] = out
    rd.finish()
    return labels, names, libraries


# ---------------- "Subdivision tags section" ----------------
TAG_VERTICES = (b'crease', b'corner')   # tags whose integers are output vertices
TAG_FACES = (b'hole',)                  # ... output faces
TAG_SETTINGS = (b'interpolateboundary', b'facevaryinginterpolateboundary', b'facevaryingpropagatecorners',
                b'creasemethod', b'smoothtriangles')   # integers index nothing


def decode_tags(payload, V, F, has_order):
    """The subdivision tags section of a mesh whose output has V vertices and F faces: the tags in
    order, each (name, ints, floats as Python floats, strings, float width or None)."""
    pos = 0

    def count(what, low=0):
        nonlocal pos
        n, pos = g.read_varint(payload, pos)
        need(low <= n <= len(payload) - pos, '%s %d (%d bytes left)' % (what, n, len(payload) - pos))
        return n

    def text(what):
        nonlocal pos
        n = count(what + ' length', 1)
        t = payload[pos:pos + n]
        need(all(c > 0x20 for c in t), '%s %r with a byte <= 0x20' % (what, t))
        pos += n
        return t

    tags = []
    for _ in range(count('tag count', 1)):
        name = text('tag name')
        ni = count('%s: int count' % name.decode('latin-1'))
        nf = count('%s: float count' % name.decode('latin-1'))
        ns = count('%s: string count' % name.decode('latin-1'))
        ints = []
        for _ in range(ni):
            z, pos = g.read_varint(payload, pos)
            ints.append(z >> 1 if not z & 1 else -(z >> 1) - 1)   # unzigzag
        width = None
        floats = []
        if nf:
            need(pos < len(payload), 'float width past the section')
            width = payload[pos]
            pos += 1
            need(width in (4, 8), 'float width %d' % width)
            need(nf * width <= len(payload) - pos, '%d floats past the section' % nf)
            fmt = '<f' if width == 4 else '<d'
            for _ in range(nf):
                x = struct.unpack(fmt, payload[pos:pos + width])[0]
                need(math.isfinite(x), 'tag float %r' % x)
                floats.append(x)
                pos += width
            seen('tags: binary%d' % (8 * width))
        strings = [text('tag string') for _ in range(ns)]
        if name in TAG_VERTICES or name in TAG_FACES:
            n = V if name in TAG_VERTICES else F
            # (negative indices are not "below the count" in any sense an index can be: refused)
            need(all(0 <= i < n for i in ints), '%s index out of 0 .. %d' % (name.decode(), n - 1))
            need(name != b'crease' or len(ints) % 2 == 0, 'crease with %d integers' % len(ints))
            seen('tags: ' + name.decode())
        elif name in TAG_SETTINGS:
            seen('tags: setting')
        else:
            need(has_order, 'tag %r indexes the mesh file\'s numbering, and the file has no order section'
                 % name)
            seen('tags: other name, order kept')
        tags.append((name, ints, floats, strings, width))
    need(pos == len(payload), 'bytes after the last tag')
    return tags


# ---------------- "Order section" ----------------
def decode_order(payload, V, degrees):
    """The order section over a mesh of V vertices and faces of these degrees (canonical order):
    (c_j per original vertex j, (c_f, r) per original face f)."""
    rd = g.RangeDecoder(payload)
    T = {}

    def t(name):
        if name not in T:
            T[name] = g.Table()
        return T[name]

    def permutation(n, step):
        """c_j for j = 0 .. n-1: each coded as zigzag(s) through step[z], s = c_j - p mod n in
        (-n/2, n/2], p = c_{j-1} + 1 mod n (0 for j = 0), z = 1 after a coded 0 (and at j = 0)."""
        out, used = [], [False] * n
        z = 1
        for j in range(n):
            p = (out[-1] + 1) % n if j else 0
            coded = rd.integer(t('%s%d' % (step, z)))
            s = g.unzigzag(coded)
            need(-n < 2 * s <= n, '%s: step %d outside (-n/2, n/2] for n = %d' % (step, s, n))
            c = (p + s) % n
            need(not used[c], '%s: index %d used twice' % (step, c))
            used[c] = True
            out.append(c)
            z = int(coded == 0)
            yield c, j

    cv = [c for c, _ in permutation(V, 'vstep')]
    faces = []
    r_prev = 0                      # the previous quad's rotation
    for c, f in permutation(len(degrees), 'fstep'):
        d = degrees[c]
        if d == 4:
            hi = rd.bit(t('rotation')[3 * r_prev])
            lo = rd.bit(t('rotation')[3 * r_prev + 1 + hi])
            r = 2 * hi + lo
            r_prev = r
            seen('order: quad rotation')
        else:
            r = rd.integer(t('turn%d' % (0 if d == 3 else 1)))
            need(r < d, 'rotation %d of a face of degree %d' % (r, d))
            seen('order: turn %s' % ('triangle' if d == 3 else 'big'))
        faces.append((c, r))
    rd.finish()
    return cv, faces


# ---------------- "Texture coordinates section" ----------------
MAX_TEXCOORDS = 1 << 26           # the reference decoder's default max_texcoords
MAX_NORMALS = 1 << 26             # ... and max_normals
ACROSS_ANY_DEGREE = True          # the quad across O -> A in a face of degree > 4 too, where O -> A is a
                                  # chord (the text's E(x, y) goes by names; qsp does so)


def round_half_away(z):
    """round(z) of a binary64 z, halfway cases away from zero."""
    f = math.floor(z)
    return f + 1 if z - f > 0.5 or (z - f == 0.5 and z > 0) else f


ROUND = round_half_away   # round(y * 10^k): the text does not say how a halfway y * 10^k rounds (an
                          # encoder writes such values: texgen.py's `uh`); qsp rounds it away from 0
FLOAT_FROM_ZERO = True    # a float prediction's binary64 sum starts from +0.0, so (-0.0, 2) alone
                          # predicts +0.0 (the text does not say; qsp does so: texgen.py's `u`)


def decode_texcoords(payload, positions, faces, has_order, normals=False, minor=10, mirror=None):
    """The texture coordinates section over the output mesh of the other sections (faces in
    canonical order, corners from each face's first): (values, names, original, modes) with
    values[i] the K components of value i as binary32 bits, names[f][k] the value corner k of face f
    names (None: none), original[i] value i's original index (None without bit 2), modes the K
    components' modes. normals: the normals section ("Normals section": the same payload with models
    of its own, which each call's are, K = 3 and T bounded by max_normals; from 3.`minor` = 10 its flag
    bits 5, from the faces, and 6, octahedral). mirror: per output vertex its image M(v) under the
    symmetry section's map (None where none), in a file with a symmetry section and no polygons
    section, else None; texture coordinates' flag bit 5 (3.18, "Mirror") reads it."""
    noun, prefix = ('normal', 'normals: ') if normals else ('texture coordinate', 'tex: ')

    def need(ok, msg):
        g.need(ok, msg.replace('texture coordinate', noun))

    def seen(what):
        _seen(what.replace('tex: ', prefix, 1))

    need(len(payload) >= 1, 'empty texture coordinates section')
    flags = payload[0]
    K = flags & 3
    need(K != 0, 'texture coordinates with 0 components')
    if normals:
        need(K == 3, 'normals with %d components (flags bits 0-1), not 3' % K)
    faces_bit = normals and bool(flags & 32)
    octahedral = normals and bool(flags & 64)
    need((flags >> 7 if normals else (flags >> 6) & 1) == 0, 'reserved texture coordinates flag bits set')
    hints = not normals and bool(flags & 128)
    mirrored = not normals and bool(flags & 32)   # "Mirror" (3.18); the normals' bit 5 is "from the faces"
    need(not mirrored or minor >= 18,
         'flag bit 5 (mirror prediction) is format 3.18\'s, and the file says it is 3.%d' % minor)
    need(not mirrored or mirror is not None,
         'flag bit 5 (mirror prediction) without a symmetry section (or beside a polygons section)')
    if not normals:
        seen('tex: %s' % ('mirror' if mirrored else 'no mirror'))
    need(not hints or minor >= 16, 'flag bit 7 (hints from the faces across) is format 3.16\'s, and the file says it is 3.%d' % minor)
    if not normals:
        seen('tex: %s' % ('hints' if hints else 'no hints'))
    need(not (faces_bit or octahedral) or minor >= 10,
         'normals predicted from the faces or octahedral are format 3.10\'s, and the file says it is 3.%d' % minor)
    kept = bool(flags & 4)
    corrections = bool(flags & 8)
    shapes = bool(flags & 16)
    need(not octahedral or not (corrections or shapes), 'octahedral normals with bits 3 or 4')
    if normals:
        seen('nrm: %s%s' % ('from the faces' if faces_bit else 'not from the faces', ', octahedral' if octahedral else ''))
    need(not (corrections and shapes), 'texture coordinates flag bits 3 and 4 both set')
    seen('tex: flag %s' % ('corrections' if corrections else 'shapes' if shapes else 'neither'))
    need(kept == has_order, 'texture coordinates order bit %d, order section %s' % (kept, has_order))
    T, pos = g.read_varint(payload, 1)
    need(T <= (1 << 31) - 1, 'more than 2^31 - 1 texture coordinates')
    if normals:
        need(T <= MAX_NORMALS, 'normals past max_normals')
    else:
        need(T <= MAX_TEXCOORDS, 'texture coordinates past max_texcoords')
    U, pos = g.read_varint(payload, pos)
    need(T <= 8192 * (len(payload) - pos + 8), '%d texture coordinates in %d bytes' % (T, len(payload) - pos))
    need(U <= T, 'more unreferenced texture coordinates than values')
    ncorners = sum(len(f) for f in faces)
    need(T - U <= ncorners, 'more named texture coordinates (%d) than corners (%d)' % (T - U, ncorners))
    if octahedral:   # one byte, bits, for the modes
        need(pos + 1 <= len(payload), 'octahedral bits past the section')
        bits = payload[pos]
        need(2 <= bits <= 24, 'octahedral bits %d' % bits)
        pos += 1 - K
        modes = []
    else:
        need(pos + K <= len(payload), 'modes past the section')
        modes = list(payload[pos:pos + K])
    for mode in modes:
        need(mode <= 10 or 17 <= mode <= 40, 'texture coordinate mode %d' % mode)
        seen('tex: K=%d mode %s' % (K, 'float' if mode == 0 else 'dec%d' % (mode - 1) if mode <= 10
                                    else 'bin%d' % (mode - 16)))
    pos += K
    signs = 0
    if mirrored:   # "Mirror": one byte, bit c set = component c reflected
        need(pos + 1 <= len(payload), 'mirror signs past the section')
        signs = payload[pos]
        need(signs >> K == 0, 'mirror sign bits 0x%02x beyond the %d components' % (signs, K))
        seen('tex: mirror signs %d of K=%d' % (signs, K))
        pos += 1
    rd = g.RangeDecoder(payload[pos:])
    T_ = {}

    def t(name):
        if name not in T_:
            T_[name] = g.Table()
        return T_[name]

    def bit(name, key=0):
        return rd.bit(t(name)[key])

    # Corner symbols
    corners = []                   # (face, position, degree)
    verts = []
    for fi, f in enumerate(faces):
        for p, v in enumerate(f):
            corners.append((fi, p, len(f)))
            verts.append(v)
    S = [[] for _ in range(len(positions))]
    name = []
    creator = []
    n = 0
    e = 0                          # an earlier corner of this face took a value other than its vertex's first
    start = [0]                    # each face's first corner (and one past the last)
    for f in faces:
        start.append(start[-1] + len(f))
    W = {}                         # "Hints": W(x, y), the first corner at x whose face's next corner is at y
    if hints or mirrored:
        for fi in range(len(faces)):
            d = len(faces[fi])
            for p in range(d):
                key = (faces[fi][p], faces[fi][(p + 1) % d])
                if key not in W:
                    W[key] = start[fi] + p
    nxt = lambda k: start[corners[k][0]] + (corners[k][1] + 1) % corners[k][2]

    def hint_of(c, v):
        """(h, H) at corner c ("Hints"), from the corners before it."""
        fi, p, d = corners[c]
        if p == 0:
            return 0, None
        h = 0
        A = c - 1
        k = W.get((v, verts[A]))
        if k is not None and corners[k][0] < fi:
            if name[nxt(k)] == name[A] and name[k] is not None:
                seen('tex: hint across the edge before')
                return 1, name[k]
            h = 2
        if p == d - 1:
            B = start[fi]
            k = W.get((verts[B], v))
            if k is not None and corners[k][0] < fi:
                if name[k] == name[B] and name[nxt(k)] is not None:
                    seen('tex: hint across the edge after the last corner')
                    return 1, name[nxt(k)]
                h = 2
        return h, None

    for c, v in enumerate(verts):
        if corners[c][1] == 0:
            e = 0
        Sv = S[v]
        s = 2 * min(len(Sv), 2) + e
        h, H = hint_of(c, v) if hints and Sv else (0, None)
        if h == 2:
            seen('tex: hint state 2 (a seam)')
        if h == 1 and bit('is_hint', s):
            seen('tex: names the hint')
            need(H in Sv, 'the hint is not a value of S(v)')   # cannot happen; the text says so
            if Sv.index(H) >= 1:
                e = 1
            name.append(H)
            continue
        if h == 1:
            seen('tex: does not name the hint')
        s += 6 * h
        if bit('is_new', s):
            seen('tex: new')
            if Sv:
                e = 1
            Sv.append(n)
            creator.append(c)
            name.append(n)
            n += 1
            need(n <= T - U, 'more named texture coordinates than T - U')
        elif Sv and bit('is_seen', s):
            j = rd.integer(t('pick%d' % (e + 2 * min(h, 1)))) if len(Sv) >= 2 else 0
            if j >= 1:
                e = 1
            seen('tex: seen, pick' if len(Sv) >= 2 else 'tex: seen')
            need(j < len(Sv), 'pick %d past S(v) of %d' % (j, len(Sv)))
            name.append(Sv[j])
        elif bit('is_none'):
            seen('tex: none')
            name.append(None)
        else:
            need(n > 0, 'a far reference before any value')
            m = n - 1 - rd.integer(t('far'))
            need(m >= 0, 'far reference before value 0')
            if m in Sv:   # the encoder would have said seen; a decoder need not check it
                seen('tex: far to a value of S(v)')
            seen('tex: far')
            e = 1
            Sv.append(m)
            name.append(m)
    need(n == T - U, 'named texture coordinates %d, T - U = %d' % (n, T - U))

    # Values
    LIM = (1 << 40) - 1
    corner_at = lambda fi, p: start[fi] + p % (start[fi + 1] - start[fi])
    # "Edges": E(x, y), the first corner naming x whose face's next corner names y
    E = {}
    for fi in range(len(faces)):
        for p in range(start[fi + 1] - start[fi]):
            c = start[fi] + p
            x, y = name[c], name[corner_at(fi, p + 1)]
            if x is not None and y is not None and (x, y) not in E:
                E[x, y] = c
    vals = []                      # per value: K components as binary32 bits
    ints = []                      # per value: K components' integers (grid modes; None in float bits)
    size = []                      # "Buckets": per value, the sum of min(|r|, 2^20) of its residuals

    def residual(key):
        z = rd.integer(t('residual%d' % key))
        if z == (1 << 32) - 2:
            seen('tex: escape')
            hi = lo = 0
            for _ in range(21):
                hi = 2 * hi + rd.raw()
            for _ in range(21):
                lo = 2 * lo + rd.raw()
            z += (hi << 21) | lo
        return g.unzigzag(z)

    def integer_of(u, mode):
        """The integer the mode maps a decoded binary32 y back to: round(y * 2^b), or round(y * 10^k)
        in binary64."""
        y = g.bits_f32(u)
        if mode >= 17:
            z = y * float(1 << (mode - 16))       # exact
        else:
            z = y * float(10 ** (mode - 1))       # one binary64 rounding
        r = ROUND(z)
        if r - z in (0.5, -0.5):
            seen('tex: integer of a value halfway (%s)' % ('binary' if mode >= 17 else 'decimal'))
        if z != r:
            seen('tex: y * 10^k not an integer' if mode < 17 else 'tex: y * 2^b not an integer')
        return r

    def shape(A, B, O, C, unfitted=(1.0, 1.0)):
        """(alpha, beta) fitting the face's 3D corners ("Shapes"), every step one binary64 operation."""
        PA, PB, PO, PC = ([g.bits_f32(u) for u in positions[verts[cc]]] for cc in (A, B, O, C))
        ea = [PA[t] - PO[t] for t in range(3)]
        eb = [PB[t] - PO[t] for t in range(3)]
        ec = [PC[t] - PO[t] for t in range(3)]
        dot = lambda x_, y_: (x_[0] * y_[0] + x_[1] * y_[1]) + x_[2] * y_[2]
        aa, bb, ab, ac, bc = dot(ea, ea), dot(eb, eb), dot(ea, eb), dot(ea, ec), dot(eb, ec)
        det = aa * bb - ab * ab
        if det > 2.0 ** -40 * (aa * bb):
            al = (ac * bb - bc * ab) / det
            be = (bc * aa - ac * ab) / det
            if abs(al) <= 4 and abs(be) <= 4:
                seen('tex: shape fitted%s' % (' (grid line)' if unfitted[0] == 0 else ''))
                return al, be
            seen('tex: shape far from a parallelogram')
        else:
            seen('tex: shape of a degenerate face')
        return unfitted

    # "Face normals": per named value, its faces' Newell normals summed, normalised (or None)
    G = [None] * (T - U)
    if faces_bit or octahedral:
        sums = [[0.0, 0.0, 0.0] for _ in range(T - U)]
        for fi, f in enumerate(faces):
            P = [[g.bits_f32(u) for u in positions[v]] for v in f]
            N = [0.0, 0.0, 0.0]
            for a_ in range(len(f)):
                pi, pj = P[a_], P[(a_ + 1) % len(f)]
                N[0] += (pi[1] - pj[1]) * (pi[2] + pj[2])
                N[1] += (pi[2] - pj[2]) * (pi[0] + pj[0])
                N[2] += (pi[0] - pj[0]) * (pi[1] + pj[1])
            for p_ in range(len(f)):
                x_ = name[start[fi] + p_]
                if x_ is not None:
                    for k in range(3):
                        sums[x_][k] += N[k]
        for x_, S3 in enumerate(sums):
            L = math.sqrt((S3[0] * S3[0] + S3[1] * S3[1]) + S3[2] * S3[2])
            if L > 0 and L != math.inf:
                G[x_] = [S3[0] / L, S3[1] / L, S3[2] / L]
            else:
                seen('nrm: a value without a face normal')

    def sgn(w):
        return -1 if w < 0 else 1

    if octahedral:   # "Octahedral normals"
        h = (1 << (bits - 1)) - 1
        prev = [0.0, 0.0, 1.0]
        for i in range(T):
            fromG = faces_bit and i < T - U and G[i] is not None
            p3 = G[i] if fromG else prev
            m = p3[2] < 0
            pz = -p3[2] if m else p3[2]
            a_ = (abs(p3[0]) + abs(p3[1])) + abs(pz)
            if a_ > 0 and a_ != math.inf:
                u_, v_ = p3[0] / a_, p3[1] / a_
                if pz / a_ < 0:
                    u_, v_ = (1 - abs(v_)) * sgn(u_), (1 - abs(u_)) * sgn(v_)
                ps, pt = ROUND(u_ * h), ROUND(v_ * h)
            else:
                ps, pt = 0, 0
            ctx = 0 if fromG else 1
            s_ = ps + residual(2 * ctx)
            t_ = pt + residual(2 * ctx + 1)
            need(-h <= s_ <= h and -h <= t_ <= h, 'octahedral integer outside [-h, h]')
            X, Y, Z = s_, t_, h - abs(s_) - abs(t_)
            if Z < 0:
                X, Y = (h - abs(t_)) * sgn(s_), (h - abs(s_)) * sgn(t_)
                seen('nrm: octahedral lower half')
            if m:
                Z = -Z
                seen('nrm: octahedral mirror')
            L = math.sqrt((float(X * X) + float(Y * Y)) + float(Z * Z))
            val = [g.f32_bits_of_double(float(X) / L), g.f32_bits_of_double(float(Y) / L),
                   g.f32_bits_of_double(float(Z) / L)]
            vals.append(val)
            prev = [g.bits_f32(u) for u in val]
        T_range = []
    else:
        T_range = range(T)

    # "Mirror" (flag bit 5): corner c's mirror image, the corner after k = W(M(v(c')), M(v(c))) in its
    # face (c' the corner after c in its face), which is at M(v(c)); None where any step gives none.
    def mirror_image(c):
        a, b = mirror[verts[c]], mirror[verts[nxt(c)]]
        if a is None or b is None:
            seen('tex: mirror: a vertex without an image')
            return None
        k = W.get((b, a))
        if k is None:
            seen('tex: mirror: no edge from M(v(c\')) to M(v(c))')
            return None
        return nxt(k)

    sigma = [-1 if signs >> k & 1 else 1 for k in range(K)]
    offset = [0] * K               # per component, what the last mirrored value left (0 before the first)
    for i in T_range:
        if mirrored and i < T - U:    # "Mirror": predicted from the value j its creating corner's image names
            mc = mirror_image(creator[i])
            j = None if mc is None else name[mc]
            if mc is not None and (j is None or j >= i):
                seen('tex: mirror: the image names %s' % ('none' if j is None else 'value i' if j == i
                                                            else 'a later value'))
            if j is not None and j < i:
                seen('tex: mirrored')
                gb = 0
                if hints:   # the bucket of the one value it reads
                    gb = min(size[j].bit_length(), 3)
                    seen('tex: mirror bucket %d' % gb)
                    size.append(0)
                val, vint = [], []
                for k in range(K):
                    mode = modes[k]
                    Ij = ints[j][k] if mode else g.image(vals[j][k])
                    p_ = sigma[k] * Ij + offset[k]
                    P = g.clamp(p_, -LIM, LIM) if mode else g.clamp(p_, 0, (1 << 32) - 1)
                    if P != p_:
                        seen('tex: mirror prediction clamped')
                    r = residual(4 * (K * 7 + k) + gb if hints else K * 7 + k)
                    if hints:
                        size[i] += min(abs(r), 1 << 20)
                    if mode:
                        q = P + r
                        need(-LIM <= q <= LIM, 'texture coordinate integer %d outside (-2^40, 2^40)' % q)
                        u = g.f32_of_rational(q, 1 << (mode - 16) if mode >= 17 else 10 ** (mode - 1))
                        Ii = integer_of(u, mode)
                        vint.append(Ii)
                    else:
                        Ii = P + r
                        need(0 <= Ii < 1 << 32, 'texture coordinate image outside [0, 2^32)')
                        u = g.unimage(Ii)
                        need(u & 0x7F800000 != 0x7F800000, 'texture coordinate not finite')
                        vint.append(None)
                    val.append(u)
                    offset[k] = Ii - sigma[k] * Ij
                vals.append(val)
                ints.append(vint)
                continue
        if faces_bit and i < T - U:   # bit 5: the value the corner before its creating corner names
            fi_, p_c, _ = corners[creator[i]]
            j = name[creator[i] - 1] if p_c >= 1 else None
            if j is not None and bit('copy'):
                seen('nrm: copy')
                vals.append(list(vals[j]))
                ints.append(list(ints[j]))
                continue
        x, terms, para = 2, None, None   # terms: (value index, weight); para: (a, b, o, alpha, beta)
        if i < T - U:
            c = creator[i]
            fi, p, d = corners[c]
            A, B = corner_at(fi, p - 1), corner_at(fi, p + 1)
            O = corner_at(fi, p + 2) if d >= 4 else None
            known = lambda cc: cc is not None and name[cc] is not None and name[cc] < i

            across_corners = []              # the corners of the last quad across found

            def across(X, Y):
                """The quad across the edge X -> Y: the values (q0, q1, q2, q3), or None."""
                k = E.get((name[Y], name[X]))
                if k is None:
                    return None
                kf = corners[k][0]
                if start[kf + 1] - start[kf] != 4:
                    seen('tex: edge across in a face not a quad')
                    return None
                kp = corners[k][1]
                qs = [corner_at(kf, kp + j) for j in range(4)]
                if not all(known(cc) for cc in qs):
                    seen('tex: quad across not known')
                    return None
                if kf == fi:
                    seen('tex: quad across is the face itself')
                if d > 4 and Y == A:
                    seen('tex: quad across the chord O -> A of a face of degree %s' % ('5' if d == 5 else '> 5'))
                across_corners[:] = qs
                return [name[cc] for cc in qs]

            def across_seam(k, from_a):
                """"Across a seam" (bit 7): the terms (c', 2), (n', -2) of the twin k, or none."""
                if not hints or k is None:
                    return []
                here, there = (k, nxt(k)) if from_a else (nxt(k), k)
                if not (known(here) and known(there)):
                    seen('tex: across a seam, not known')
                    return []
                seen('tex: across a seam from %s' % ('A' if from_a else 'B'))
                return [(name[here], 2), (name[there], -2)]

            # (O -> A is an edge of the face only if d = 4; the text finds the quad across by names)
            across_oa = (lambda: across(O, A)) if ACROSS_ANY_DEGREE or d == 4 else (lambda: None)
            across_bo = lambda: across(B, O)
            a = name[A] if known(A) else None
            b = name[B] if known(B) else None
            o = name[O] if known(O) else None
            if a is not None and b is not None and o is not None:
                x, terms, para = 0, [], (a, b, o) + (shape(A, B, O, c) if shapes else (1.0, 1.0))
                if corrections:
                    l, m = across_oa(), across_bo()
                    w = 1 if l and m else 2
                    if l:
                        terms += [(l[0], w), (l[1], -w), (l[3], -w), (l[2], w)]
                    if m:
                        terms += [(m[1], w), (m[0], -w), (m[2], -w), (m[3], w)]
                    if l or m:
                        x = 3
                        seen('tex: corrections %s' % ('both' if l and m else 'l' if l else 'm'))
                if d > 4:
                    seen('tex: parallelogram in a face of degree > 4')
            elif a is not None:       # the grid line: a parallelogram with origin A, O in the place
                l = across_oa() if o is not None else None   # of A and l3's corner in the place of B
                if l:
                    L3 = across_corners[3]
                    x, terms, para = 4, [], (o, l[3], a) + (shape(O, L3, A, c, (0.0, -1.0)) if shapes else (0.0, -1.0))
                else:
                    x, terms = 1, [(a, 2)] + across_seam(W.get((verts[c], verts[A])), True)
                if l and d > 4:
                    seen('tex: grid line in a face of degree > 4')
            elif b is not None:
                m = across_bo() if o is not None else None
                if m:
                    M2 = across_corners[2]
                    x, terms, para = 4, [], (o, m[2], b) + (shape(O, M2, B, c, (0.0, -1.0)) if shapes else (0.0, -1.0))
                else:
                    x, terms = 1, [(b, 2)] + across_seam(W.get((verts[B], verts[c])), False)
                if m and d > 4:
                    seen('tex: grid line in a face of degree > 4')
        if terms is None:
            terms = [(i - 1, 2)] if i else []
            para = None
        elif x == 1:
            para = None
            if len(terms) == 3:   # across a seam
                x = 6
        if faces_bit and i < T - U and G[i] is not None:   # bit 5: the face normal predicts it
            x, terms, para = 5, None, None
        seen('tex: x=%d' % x)
        val, vint = [], []
        gb = 0
        if hints:
            reads = ([para[0], para[1], para[2]] if para else []) + [j for j, _ in (terms or [])]
            if reads:
                gb = min(int(sum(size[j] for j in reads) // len(reads)).bit_length(), 3)
            seen('tex: bucket %d' % gb)
            size.append(0)
        for k in range(K):
            mode = modes[k]
            r = residual(4 * (K * x + k) + gb if hints else K * x + k)
            if hints:
                size[i] += min(abs(r), 1 << 20)
            if mode:
                if x == 5:   # bit 5: the integer of the face normal's component in the mode
                    Gk = G[i][k]
                    pred = ROUND(Gk * float(1 << (mode - 16)) if mode >= 17 else Gk * float(10 ** (mode - 1)))
                else:
                    S_ = sum(w * ints[j][k] for j, w in terms)
                    if S_ & 1:
                        seen('tex: odd integer sum')
                    if para:
                        qa, qb, qo = (ints[j][k] for j in para[:3])
                        al, be = para[3:]
                        p_ = math.floor((((float(S_) + float(2 * qo)) / 2 + (al * (float(qa) - float(qo)) + be * (float(qb) - float(qo)))) + 0.5))
                        if (al, be) == (1.0, 1.0) and p_ != (S_ + 1) // 2 + qa + qb - qo:
                            seen('tex: binary64 parallelogram not exact')
                    elif terms:
                        p_ = (S_ + 1) >> 1
                    pred = g.clamp(p_, -LIM, LIM) if terms or para else 0
                    if (terms or para) and pred != p_:
                        seen('tex: clamped prediction')
                q = pred + r
                need(-LIM <= q <= LIM, 'texture coordinate integer %d outside (-2^40, 2^40)' % q)
                den = 1 << (mode - 16) if mode >= 17 else 10 ** (mode - 1)
                u = g.f32_of_rational(q, den)
                if faces_bit and q == 0 and bit('minus', k):   # bit 5: a grid's -0
                    seen('nrm: -0 on a grid')
                    u = 0x80000000
                val.append(u)
                vint.append(integer_of(u, mode))
            elif x == 5:   # float bits: the image of G's component rounded to binary32
                im = g.image(g.f32_bits_of_double(G[i][k])) + r
                need(0 <= im < 1 << 32, 'texture coordinate image outside [0, 2^32)')
                u = g.unimage(im)
                need(u & 0x7F800000 != 0x7F800000, 'texture coordinate not finite')
                val.append(u)
                vint.append(None)
            else:
                if terms or para:
                    acc = 0.0 if FLOAT_FROM_ZERO else None
                    for j, w in terms:
                        v = w * g.bits_f32(vals[j][k])
                        acc = v if acc is None else acc + v
                    if para:
                        fa, fb_, fo = (g.bits_f32(vals[j][k]) for j in para[:3])
                        al, be = para[3:]
                        pd = (fo + al * (fa - fo)) + be * (fb_ - fo)
                        if acc is not None:
                            pd = pd + acc / 2
                        pb = g.f32_bits_of_double(pd)
                        first = vals[para[0]][k]
                    else:
                        pb = g.f32_bits_of_double(acc / 2)
                        first = vals[terms[0][0]][k]
                    if pb & 0x7FFFFFFF == 0x7F800000:
                        seen('tex: infinite prediction')
                        pb = first
                else:
                    pb = 0                 # 0.0
                im = g.image(pb) + r
                need(0 <= im < 1 << 32, 'texture coordinate image outside [0, 2^32)')
                u = g.unimage(im)
                need(u & 0x7F800000 != 0x7F800000, 'texture coordinate not finite')
                val.append(u)
                vint.append(None)
        vals.append(val)
        ints.append(vint)
    values = [tuple(v) for v in vals]
    unref = values[T - U:]
    # (the encoder sorts them by the bits it was given, before a binary grid rounds them)
    if unref != sorted(unref) and not octahedral and not any(mode >= 17 for mode in modes):
        seen('tex: unreferenced values not sorted (an encoder rule)')

    # Original numbering
    original = None
    if kept:
        original = []
        used = [False] * T
        z = 1
        for i in range(T):
            p_ = (original[-1] + 1) % T if i else 0
            coded = rd.integer(t('step%d' % z))
            s = g.unzigzag(coded)
            need(-T < 2 * s <= T, 'texture coordinate step outside (-T/2, T/2]')
            j = (p_ + s) % T
            need(not used[j], 'original texture coordinate index used twice')
            used[j] = True
            original.append(j)
            z = int(coded == 0)
    rd.finish()
    names = [name[start[fi]:start[fi + 1]] for fi in range(len(faces))]
    return values, names, original, modes


# ---------------- "Interior positions section" (3.12) ----------------
def interior_count(payload, I):
    """The interior positions section: N, 1 <= N <= I (the count of owned interior refs is checked
    by the caller)."""
    N, pos = g.read_varint(payload, 0)
    need(pos == len(payload), 'bytes after the interior positions section\'s count')
    need(1 <= N <= I, 'interior position count %d, the polygons section has %d interior refs' % (N, I))
    return N


def interior_stencils(V, L, N, at, owner, faces):
    """"Interior stencils": the stencils of coding positions V .. V+N-1, those of the output vertices
    L .. L+N-1 (the owned interior refs, in ref order). at[v]: the coding position of layout vertex v;
    owner[u]: the layout ref that owns output vertex u < L; faces: the output faces (output vertices)
    in output order."""
    pos = lambda u: at[owner[u]] if u < L else V + (u - L)
    around = [[] for _ in range(N)]   # per interior output vertex, (b, a) of each face that has it
    for f in faces:
        d = len(f)
        for i, u in enumerate(f):
            if u >= L:
                around[u - L].append((f[i - 1], f[(i + 1) % d]))
    out = []
    for j in range(N):
        k = V + j
        s = lay.blank()
        out.append(s)
        occ = around[j]
        need(occ, 'interior output vertex %d in no face' % (L + j))  # (every created ref is listed)
        by_b = {}                     # b -> the faces with that b, in output order, and a cursor
        for x, (b, a) in enumerate(occ):
            by_b.setdefault(b, [[], 0])[0].append(x)
        taken = [False] * len(occ)
        taken[0] = True
        fan = list(occ[0])
        closed = False
        while True:
            entry = by_b.get(fan[-1])
            if entry is None:
                break
            lst, c = entry
            while c < len(lst) and taken[lst[c]]:
                c += 1
            entry[1] = c
            if c == len(lst):
                break
            taken[lst[c]] = True
            a = occ[lst[c]][1]
            if a == fan[0]:
                closed = True
                break
            fan.append(a)
        n = len(fan)
        seen('interior: %s fan' % ('closed' if closed else 'open'))
        if not all(taken):
            seen('interior: a face never taken')
        i = next((i for i, y in enumerate(fan) if pos(y) < k), None)
        if i is None:
            seen('interior: empty stencil')
            continue
        s['w'] = pos(fan[i])
        if closed:
            z = fan[(i + n // 2) % n]
        else:
            z = fan[n - 1] if n - 1 > i else None
        if z is not None and pos(z) < k and z != fan[i]:
            s['far'], s['far_dist'] = pos(z), 1
            seen('interior: w and far')
        else:
            seen('interior: w only')
    return out


# ---------------- "Decoding a mesh" ----------------
def output_numbering(V, I, groups):
    """"Interior positions and output": (class of each glued ref, output vertex of each ref that is
    the smallest of its class)."""
    first_of = {}
    for grp in groups:
        for r in grp:
            first_of[r] = grp[0]
    out_index = {}
    for r in range(V + I):
        if first_of.get(r, r) == r:
            out_index[r] = len(out_index)
    return first_of, out_index


def canonical_mesh(data, secs, images=False):
    """The output mesh before an order section: (positions as float bits, faces, quantized?), and
    with images the mirror image of each output vertex (the symmetry section's map, None where it
    gives none) or None (no symmetry section, or a polygons section: "Mirror" of the texture
    coordinates section reads it only where the layout's vertices are the output's)."""
    V, F, C, U = g.counts(secs[1])
    n, quads = layout(secs[2], C, U)
    need(n == V and len(quads) == F, 'counts disagree with the topology')
    geo = secs[3]
    coding, st = lay.stencils(secs[2], C, U, bool(geo[0] & g.LAYOUT_ORDER))
    vmap = qspmirror.file_map(data, secs, V, quads)   # "Symmetry section" (3.17)
    mirror = None
    if vmap is not None:
        seen('symmetry section')
        mirror = qspmirror.mirror_sources(coding, *vmap)
    if 0x0c in secs:
        out = interior_mesh(data, secs, V, quads, coding, st, mirror)
        return out + (None,) if images else out
    fb, _ = g.decode_geometry(geo, V, st, mirror=mirror)
    pos = [None] * V
    for k in range(V):
        pos[coding[k]] = (fb[0][k], fb[1][k], fb[2][k])
    if 0x05 not in secs:
        out = pos, [list(q) for q in quads], geo[1] != 0
        return out + (vmap and vmap[0],) if images else out
    need(data[9] >= 1, 'a polygons section in a 3.0 file')
    I, groups, faces, rest = decode_polygons(secs[0x05], V, quads)
    first_of, out_index = output_numbering(V, I, groups)
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
    return (out_pos, out_faces, geo[1] != 0) + ((None,) if images else ())


def interior_mesh(data, secs, V, quads, coding, st, mirror=None):
    """canonical_mesh of a file with an interior positions section (3.12): the polygons section's
    faces first, then the geometry section over V + N vertices, the owned interior refs' positions
    at coding positions V .. V+N-1."""
    need(0x05 in secs, 'section 0x0c (interior positions) without a polygons section')
    need(data[9] >= 12, 'section 0x0c (interior positions) is format 3.12\'s, and the file says it is 3.%d'
         % data[9])
    I, groups, faces, rest = decode_polygons(secs[0x05], V, quads)
    need(len(rest) == 0, '%d bytes after the polygons section\'s stream, with an interior positions section'
         % len(rest))
    N = interior_count(secs[0x0c], I)
    first_of, out_index = output_numbering(V, I, groups)
    owned = [r for r in range(V, V + I) if r in out_index]
    need(N == len(owned), 'interior position count %d, the polygons section gives %d owned interior refs'
         % (N, len(owned)))
    L = len(out_index) - N
    owner = [r for r in range(V) if r in out_index]   # output vertex u < L: its layout ref
    out_faces = []
    for f in [list(q) for q in quads] + faces:
        o = [out_index[first_of.get(r, r)] for r in f]
        need(len(set(o)) == len(o), 'a face repeating an output vertex')
        out_faces.append(o)
    at = [None] * V
    for k, v in enumerate(coding):
        at[v] = k
    geo = secs[3]
    need(V + N <= 2048 * (len(geo) + 8), 'more vertices than the geometry section can hold')
    ist = interior_stencils(V, L, N, at, owner, out_faces[len(quads):])
    fb, _ = g.decode_geometry(geo, V + N, st + ist, mirror=mirror)
    pos = [None] * V
    for k in range(V):
        pos[coding[k]] = (fb[0][k], fb[1][k], fb[2][k])
    out_pos = [pos[r] for r in owner] + [(fb[0][V + j], fb[1][V + j], fb[2][V + j]) for j in range(N)]
    seen('interior positions section')
    return out_pos, out_faces, geo[1] != 0


KNOWN_REQUIRED = (0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, 0x09, 0x0a, 0x0b, 0x0c, 0x0d, 0x0e, 0x0f)


def refusals(cases, qsp, scratch):
    """For each case (what, file bytes, valid): whether this decoder and `qsp decompress` (writing the
    file to `scratch` and an OBJ beside it) both accept it exactly when it is valid. Returns the
    disagreements as messages (check.sh's sections broken each way the text names)."""
    failed = []
    for what, b, valid in cases:
        try:
            decode_file(b)
            ok = True
        except g.FormatError:
            ok = False
        if ok != valid:
            failed.append('qsppoly.py %s %s' % ('refuses' if valid else 'does not refuse', what))
        open(scratch, 'wb').write(b)
        r = subprocess.run([qsp, 'decompress', '-f', scratch, '-o', scratch + '.obj'], capture_output=True)
        if (r.returncode == 0) != valid:
            failed.append('qsp decompress %s %s' % ('refuses' if valid else 'does not refuse', what))
    return failed


def decode_file(data):
    """(positions as float bits per output vertex, faces, comment lines, quantized?, texture
    coordinates, face labels) of the output mesh, the order section applied; texture coordinates are
    None or (values as binary32 bits per component, per face the value each corner names or None);
    face labels None or {'faces': {kind: per face its name or None}, 'unused': {kind: the names no
    face takes}, 'libraries': the mtllib texts}, for the kinds present; subdivision tags; normals None
    or [values as binary32 bits, per face the normal each corner names or None, modes], as texture
    coordinates are; exact positions None or binary64 values per vertex; colours None or {'vertex':
    None or per vertex a tuple of binary32 bits, 'face': None or the same per face, 'modes': the
    components' modes}, moved with their vertices and faces by an order section; exact values None or
    qspvalues.decode_values'; properties None or qspprops.decode_props' list, their values moved with
    their vertices and faces by an order section."""
    secs = g.sections(data)
    for tag in secs:
        need(tag & 0x80 or tag in KNOWN_REQUIRED, 'section 0x%02x is required but unknown' % tag)
    pos, faces, quantized, images = canonical_mesh(data, secs, images=True)
    exact = None   # "Exact positions section": binary64 values per output vertex, moved as positions are
    if 0x0a in secs:
        exact = qspexact.decode_exact(secs[0x0a], len(pos), [tuple(map(g.bits_f32, p)) for p in pos],
                                      quantized, data[9])
    colors = None  # "Colours section": per output vertex and face, moved as vertices and faces are
    if 0x0b in secs:
        vc, fc, modes = qspcolors.decode_colors(secs[0x0b], len(pos), len(faces), faces, data[9])
        Kv, Kf = qspcolors.parse_header(secs[0x0b], len(pos), len(faces))[:2]
        colors = {'vertex': vc, 'face': fc, 'modes': modes, 'K': (Kv, Kf)}
    props = None   # "Properties section": per output vertex and face, moved as vertices and faces are
    if 0x0e in secs:
        props = qspprops.decode_props(secs[0x0e], len(pos), len(faces), data[9])
    lines = comments(secs[0x81]) if 0x81 in secs else []
    if 0x85 in secs:
        need(data[9] >= 16, 'section 0x85 (coded comments) is format 3.16\'s, and the file says it is 3.%d'
             % data[9])
        need(0x81 not in secs, 'coded comments section beside a comments section')
        lines = coded_comments(secs[0x85])
    tex = None
    if 0x06 in secs:
        need(data[9] >= 2, 'a texture coordinates section in a %d.%d file' % (data[8], data[9]))
        values, names, original, modes = decode_texcoords(secs[0x06], pos, faces, 0x04 in secs, minor=data[9],
                                                          mirror=images)
        if original is not None:
            out_values = [None] * len(values)
            for i, j in enumerate(original):
                out_values[j] = values[i]
            names = [[None if x is None else original[x] for x in f] for f in names]
            values = out_values
        tex = [values, names, modes]
    nrm = None
    if 0x09 in secs:   # "Normals section": the texture coordinates section's payload, K = 3
        need(data[9] >= 5, 'section 0x09 (normals) in a %d.%d file' % (data[8], data[9]))
        values, names, original, modes = decode_texcoords(secs[0x09], pos, faces, 0x04 in secs, normals=True,
                                                          minor=data[9])
        if original is not None:
            out_values = [None] * len(values)
            for i, j in enumerate(original):
                out_values[j] = values[i]
            names = [[None if x is None else original[x] for x in f] for f in names]
            values = out_values
        nrm = [values, names, modes]
    labels = None
    if 0x07 in secs:
        need(data[9] >= 3, 'section 0x07 (face labels) in a %d.%d file' % (data[8], data[9]))
        lab, names, libraries = decode_labels(secs[0x07], len(faces))
        labels = {'faces': {k: [None if x is None else names[k][x] for x in lab[k]] for k in lab},
                  'unused': {k: set(names[k]) - {names[k][x] for x in lab[k] if x is not None} for k in lab},
                  'libraries': libraries}
    tags = None
    if 0x08 in secs:   # its indices are the output's already: the order section leaves them be
        need(data[9] >= 4, 'section 0x08 (subdivision tags) in a %d.%d file' % (data[8], data[9]))
        tags = decode_tags(secs[0x08], len(pos), len(faces), 0x04 in secs)
    if 0x04 in secs:
        seen('order section')
        cv, of = decode_order(secs[0x04], len(pos), [len(f) for f in faces])
        if labels:
            labels['faces'] = {k: [v[c] for c, _ in of] for k, v in labels['faces'].items()}
        back = [None] * len(pos)
        for j, c in enumerate(cv):
            back[c] = j
        opos = [pos[c] for c in cv]
        exact = exact and [exact[c] for c in cv]
        if colors and colors['vertex']:
            colors['vertex'] = [colors['vertex'][c] for c in cv]
        if colors and colors['face']:
            colors['face'] = [colors['face'][c] for c, _ in of]
        if props:
            qspprops.permute(props, cv, of)
        ofaces, onames, onormals = [], [], []
        for c, r in of:
            d = len(faces[c])
            f, nm, nn = [None] * d, [None] * d, [None] * d
            for k in range(d):
                f[(k + r) % d] = back[faces[c][k]]
                if tex:
                    nm[(k + r) % d] = tex[1][c][k]
                if nrm:
                    nn[(k + r) % d] = nrm[1][c][k]
            ofaces.append(f)
            onames.append(nm)
            onormals.append(nn)
        pos, faces = opos, ofaces
        if tex:
            tex[1] = onames
        if nrm:
            nrm[1] = onormals
    values = None  # "Exact values section": over the values as returned above, the order section applied
    if 0x0d in secs:
        values = qspvalues.decode_values(secs[0x0d], qspvalues.arrays_of(tex, nrm, colors), data[9])
    return pos, faces, lines, quantized, tex, labels, tags, nrm, exact, colors, values, props


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


def read_obj_corner_values(path, field):
    """Positions, the values one field of a corner's `v/vt/vn` names (field 1: texture coordinates,
    `vt`, every component; field 2: normals, `vn`, three components), as float32 bits per component,
    and faces with, per corner, its vertex and the value it names (0-based, None for none) of an .obj."""
    keyword, width = {1: (b'vt', None), 2: (b'vn', 3)}[field]
    pos, vals, faces, names = [], [], [], []
    for raw in open(path, 'rb').read().split(b'\n'):
        w = raw.split()
        if not w or w[0].startswith(b'#'):
            continue
        if w[0] == b'v':
            pos.append(tuple(f32(float(x)) for x in w[1:4]))
        elif w[0] == keyword:
            vals.append(tuple(f32(float(x)) for x in w[1:][:width]))
        elif w[0] == b'f':
            f, nm = [], []
            for x in w[1:]:
                parts = x.split(b'/')
                i = int(parts[0])
                f.append(i - 1 if i > 0 else len(pos) + i)
                if len(parts) > field and parts[field]:
                    k = int(parts[field])
                    nm.append(k - 1 if k > 0 else len(vals) + k)
                else:
                    nm.append(None)
            faces.append(f)
            names.append(nm)
    return pos, vals, faces, names


def compare_normals(mesh, other, what, exact):
    """The mesh's normals against read_obj_corner_values(path, 2) of an .obj, as compare_tex compares
    texture coordinates: every corner's position and normal bits up to renumbering, face order and
    rotation, and the normals no corner names; exact: index for index."""
    as_tex = tuple(mesh[:4]) + (mesh[7],)
    return [b.replace('texture coordinate', 'normal') for b in compare_tex(as_tex, other, what, exact)]


def on_grid(u, mode):
    """Binary32 bits u rounded to the binary grid of step 2^-b that mode 16 + b names (halfway: to
    even), as the decoder gives it back: the binary32 nearest to q * 2^-b."""
    b = mode - 16
    z = g.bits_f32(u) * float(1 << b)          # exact
    if z - math.floor(z) == 0.5:
        seen('tex: --quantize-uv halfway')
    return g.f32_of_rational(QUANTIZE_ROUND(z), 1 << b)


QUANTIZE_ROUND = round   # (the text does not say how --quantize-uv rounds a halfway value: qsp rounds
                         # it to even, so does Python's round of a float)


def tex_faces(pos, faces, values, names):
    """The faces as corner cycles of (position, texture coordinate or ()), each its smallest rotation
    (two corners may be equal: positions left out of a quantized mesh, a texture chart's degenerate
    face), sorted: a mesh up to vertex and texture coordinate renumbering, face order and rotation."""
    out = []
    for f, nm in zip(faces, names):
        cyc = [(pos[v], () if x is None else tuple(values[x])) for v, x in zip(f, nm)]
        out.append(min(tuple(cyc[k:] + cyc[:k]) for k in range(len(cyc))))
    return sorted(out)


def compare_tex(mesh, other, what, exact, source=False):
    """The mesh's texture coordinates against (pos, vts, faces, names) of an .obj: every corner's
    position and texture coordinate bits up to renumbering, face order and rotation, and the values
    no corner names; exact: index for index (vertex order, face order, first corners, values). source:
    the .obj the file was made from, its values rounded to the binary grids the file's modes name."""
    pos, faces, _, quantized, tex = mesh[:5]
    opos, ovts, ofaces, onames = other
    if tex is None:
        if ovts:
            return ['no texture coordinates section, %s has %d' % (what, len(ovts))]
        tex = [], [[None] * len(f) for f in faces], []
    values, names, modes = tex
    K = len(values[0]) if values else 0
    ovts = [v[:K] + (0,) * (K - len(v)) if len(v) != K else v for v in ovts]
    if source and any(mode >= 17 for mode in modes):   # --quantize-uv: the .obj's values on the grid
        ovts = [tuple(on_grid(u, mode) if mode >= 17 else u for u, mode in zip(v, modes)) for v in ovts]
    bad = []
    if exact:
        if not quantized and pos != opos:
            bad.append('positions differ from %s\'s' % what)
        if faces != ofaces:
            bad.append('faces differ from %s\'s' % what)
        if values != ovts:
            bad.append('texture coordinates differ from %s\'s (first at %s; %d and %d)' % (
                what, next((i for i in range(min(len(values), len(ovts))) if values[i] != ovts[i]), '-'),
                len(values), len(ovts)))
        if names != onames:
            bad.append('corners\' texture coordinates differ from %s\'s (first at face %s)' % (
                what, next((i for i in range(min(len(names), len(onames))) if names[i] != onames[i]), '-')))
        return bad
    if len(faces) != len(ofaces):
        return ['%d faces, %s %d' % (len(faces), what, len(ofaces))]
    if quantized:
        pos = [()] * len(pos)
        opos = [()] * len(opos)
    mine, theirs = tex_faces(pos, faces, values, names), tex_faces(opos, ofaces, ovts, onames)
    if mine != theirs:
        diff = sorted(set(mine) ^ set(theirs))
        bad.append('corners\' positions and texture coordinates differ from %s\'s (%d of %d faces; first: %s)'
                   % (what, sum(1 for a, b in zip(mine, theirs) if a != b), len(mine), diff[:1]))
    named = {x for nm in names for x in nm if x is not None}
    onamed = {x for nm in onames for x in nm if x is not None}
    free = sorted(tuple(v) for i, v in enumerate(values) if i not in named)
    ofree = sorted(tuple(v) for i, v in enumerate(ovts) if i not in onamed)
    if free != ofree:
        bad.append('texture coordinates no corner names: %d, %s\'s %d (or other values)' % (len(free), what, len(ofree)))
    if len(values) != len(ovts):
        bad.append('%d texture coordinates, %s %d' % (len(values), what, len(ovts)))
    return bad


def canon_face(f):
    k = f.index(min(f))
    return tuple(f[k:] + f[:k])


def compare_obj(path, mesh, obj_path):
    pos, faces, lines, quantized = mesh[:4]
    opos, ofaces, olead = read_obj(obj_path)
    bad = []
    if len(pos) != len(opos) or len(faces) != len(ofaces):
        return ['%d vertices and %d faces, the .obj %d and %d' % (len(pos), len(faces), len(opos), len(ofaces))]
    if not quantized and len(set(opos)) < len(opos):   # two vertices at one position (pmp_suzanne):
        seen('obj: coincident vertices')               # the faces as cycles of corner positions
        cyc = lambda p, fs: sorted(min(tuple(c[k:] + c[:k]) for k in range(len(c)))
                                   for c in ([p[v] for v in f] for f in fs))
        if sorted(pos) != sorted(opos):
            bad.append('positions differ from the .obj\'s (as multisets)')
        elif cyc(pos, faces) != cyc(opos, ofaces):
            bad.append('faces\' corner positions differ from the .obj\'s')
    elif not quantized:
        by_pos = {}
        for i, p in enumerate(opos):
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


def read_obj_labels(path):
    """Positions (float32 bits), faces (0-based), per face its labels of kinds 0..3 (the name of the
    last statement of that kind before it, None before the first; `g` names joined by single spaces),
    the mtllib texts in order, per kind the names no face takes, and the kinds stated."""
    pos, faces, labels, libraries = [], [], [], []
    current = [None] * 4
    stated = [set() for _ in range(4)]
    for raw in open(path, 'rb').read().split(b'\n'):
        line = raw[:-1] if raw.endswith(b'\r') else raw
        w = line.split()
        if not w or w[0].startswith(b'#'):
            continue
        rest = line.lstrip()[len(w[0]):].strip(b' \t')
        if w[0] == b'v':
            pos.append(tuple(f32(float(x)) for x in w[1:4]))
        elif w[0] == b'f':
            idx = [int(x.split(b'/')[0]) for x in w[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
            labels.append(tuple(current))
        elif w[0] in LABEL_KINDS:
            k = LABEL_KINDS.index(w[0])
            current[k] = b' '.join(w[1:]) if k == 1 else rest
            stated[k].add(current[k])
        elif w[0] == b'mtllib':
            libraries.append(rest)
    taken = [{f[k] for f in labels} for k in range(4)]
    unused = {k: stated[k] - taken[k] for k in range(4) if stated[k]}
    return pos, faces, labels, libraries, unused


def compare_labels(mesh, other, what, exact, unused=True):
    """The mesh's face labels and material libraries against read_obj_labels' of an .obj: per face
    (its corners' positions, its labels), as a multiset of faces up to rotation, or face by face when
    exact; the libraries, and the names no face takes if unused (the text does not say that an .obj
    writer keeps them). Positions are left out of a quantized file's."""
    pos, faces, _, quantized, _, labels = mesh[:6]
    opos, ofaces, olabels, olibraries, ounused = other
    if labels is None:
        labels = {'faces': {}, 'unused': {}, 'libraries': []}
    bad = []
    if unused and sorted(labels['faces']) != sorted(ounused):
        bad.append('label kinds %s, %s states kinds %s' % (sorted(labels['faces']), what, sorted(ounused)))
    if len(faces) != len(ofaces):
        return bad + ['%d faces, %s %d' % (len(faces), what, len(ofaces))]
    key = lambda x: (0,) if x is None else (1, x)
    mine_l = [tuple(key(labels['faces'][k][f] if k in labels['faces'] else None) for k in range(4))
              for f in range(len(faces))]
    theirs_l = [tuple(key(x) for x in t) for t in olabels]

    def cycles(p, fs):
        if quantized:
            return [()] * len(fs)
        out = []
        for f in fs:
            c = [p[v] for v in f]
            out.append(tuple(c) if exact else min(tuple(c[i:] + c[:i]) for i in range(len(c))))
        return out

    mine = list(zip(cycles(pos, faces), mine_l))
    theirs = list(zip(cycles(opos, ofaces), theirs_l))
    if exact:
        diff = [i for i in range(len(mine)) if mine[i] != theirs[i]]
        if diff and sorted(mine) == sorted(theirs):
            i = diff[0]
            bad.append('%s has the same faces with the same labels in another order (%d faces moved; '
                       'first: face %d, labels %s, there %s)' % (what, len(diff), i, mine_l[i], theirs_l[i]))
        elif diff:
            i = diff[0]
            bad.append('%d faces\' corners or labels differ from %s\'s (first: face %d, labels %s, %s\'s %s%s)' % (
                len(diff), what, i, mine_l[i], what, theirs_l[i],
                '' if mine[i][0] == theirs[i][0] else '; corners differ'))
    elif sorted(mine) != sorted(theirs):
        a, b = sorted(mine), sorted(theirs)
        i = next(i for i in range(len(a)) if a[i] != b[i])
        bad.append('faces\' corners and labels differ from %s\'s as multisets (first: labels %s, %s\'s %s%s)' % (
            what, a[i][1], what, b[i][1], '' if a[i][0] == b[i][0] else '; corners differ'))
    for k in sorted(ounused) if unused else ():
        if labels['unused'].get(k, set()) != ounused[k]:
            bad.append('kind %d: names no face takes %s, %s\'s %s' % (
                k, sorted(labels['unused'].get(k, set())), what, sorted(ounused[k])))
    if labels['libraries'] != olibraries:
        bad.append('material libraries %s, %s\'s %s' % (labels['libraries'], what, olibraries))
    return bad


def read_obj_tags(path):
    """Positions (float32 bits), faces (0-based) and `t` tags (name, ints, float texts, strings) of
    an .obj, in file order."""
    pos, faces, tags = [], [], []
    for raw in open(path, 'rb').read().split(b'\n'):
        w = raw.split()
        if not w or w[0].startswith(b'#'):
            continue
        if w[0] == b'v':
            pos.append(tuple(f32(float(x)) for x in w[1:4]))
        elif w[0] == b'f':
            idx = [int(x.split(b'/')[0]) for x in w[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
        elif w[0] == b't':
            ni, nf, ns = (int(x) for x in w[2].split(b'/'))
            args = w[3:]
            need(len(args) == ni + nf + ns,
                 '%s: t %s with %d arguments, not %d' % (path, w[1], len(args), ni + nf + ns))
            tags.append((w[1], [int(x) for x in args[:ni]], args[ni:ni + nf], args[ni + nf:]))
    return pos, faces, tags


def compare_tags(mesh, other, what, exact):
    """The mesh's tags against read_obj_tags' of an .obj, tag for tag: names, strings, floats by
    value (a binary32 one against the text read as binary32), and integers; those of crease and
    corner as the vertices they name (their positions, or index for index when exact), those of hole
    as the faces (their corner cycles up to rotation, by the same vertex keys)."""
    pos, faces = mesh[:2]
    tags = mesh[6] or []
    opos, ofaces, otags = other

    def keys(p, fs):
        vk = list(range(len(p))) if exact else p
        return vk, [canon_face([vk[v] for v in f]) for f in fs]

    vk, fk = keys(pos, faces)
    ovk, ofk = keys(opos, ofaces)

    def named(name, ints, vk, fk):
        try:
            if name in TAG_VERTICES:
                return [vk[i] for i in ints]
            if name in TAG_FACES:
                return [fk[i] for i in ints]
        except IndexError:
            return ['index out of range', ints]
        return ints

    bad = []
    if len(tags) != len(otags):
        bad.append('%d tags, %s %d' % (len(tags), what, len(otags)))
    for k, (t, o) in enumerate(zip(tags, otags)):
        name, ints, floats, strings, width = t
        oname, oints, ofloats, ostrings = o
        if name != oname:
            bad.append('tag %d: %s, %s\'s %s' % (k, name, what, oname))
            continue
        if named(name, ints, vk, fk) != named(oname, oints, ovk, ofk):
            bad.append('tag %d (%s): integers %s, %s\'s %s (or what they name differs)' % (
                k, name.decode(), ints, what, oints))
        read = (lambda x: f32(float(x))) if width == 4 else float
        mine = [f32(x) for x in floats] if width == 4 else floats
        if mine != [read(x) for x in ofloats]:
            bad.append('tag %d (%s): floats %s (binary%s), %s\'s %s' % (
                k, name.decode(), floats, 8 * (width or 0), what, [x.decode() for x in ofloats]))
        if strings != ostrings:
            bad.append('tag %d (%s): strings %s, %s\'s %s' % (k, name.decode(), strings, what, ostrings))
    return bad


OBJ_UNLABELLED_FIRST = True   # the text does not say how an OBJ writer orders faces when a label goes
                               # back to none (OBJ has no statement for none): qsp puts the faces with
                               # more kinds unlabelled first, keeping the order among equal ones


def as_obj_writes(mesh):
    """The mesh with its faces in the order an OBJ writer can label them: stably, the faces with
    more kinds unlabelled first (the decoder's order whenever no label goes back to none)."""
    pos, faces, lines, quantized, tex, labels = mesh[:6]
    if not labels or not labels['faces']:
        return mesh
    none = [sum(v[f] is None for v in labels['faces'].values()) for f in range(len(faces))]
    order = sorted(range(len(faces)), key=lambda f: -none[f])
    if order != list(range(len(faces))):
        seen('labels: faces an OBJ writer moves')
    labels = dict(labels, faces={k: [v[f] for f in order] for k, v in labels['faces'].items()})
    if tex:
        tex = [tex[0], [tex[1][f] for f in order], tex[2]]
    tags, nrm = mesh[6:8]
    if nrm:
        nrm = [nrm[0], [nrm[1][f] for f in order], nrm[2]]
    return (pos, [faces[f] for f in order], lines, quantized, tex, labels, tags, nrm)


def compare_reference(mesh, prefix):
    """Exactly the reference decoder's output (dump_stencils' PREFIX.mesh, PREFIX.comments; no
    PREFIX.mesh for a file with an order section: --decompressed compares those)."""
    import os
    pos, faces, lines = mesh[:3]
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
    opts = {a: b for a, b in zip(args[1:], args[2:]) if a.startswith('--')}
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
    if '--tex-obj' in opts:
        bad += compare_tex(mesh, read_obj_corner_values(opts['--tex-obj'], 1), 'the .obj',
                           exact='--exact' in args, source=True)
    if '--labels-obj' in opts:
        bad += compare_labels(mesh, read_obj_labels(opts['--labels-obj']), 'the .obj', exact='--exact' in args)
    written = as_obj_writes(mesh) if OBJ_UNLABELLED_FIRST else mesh
    if '--labels-decompressed' in opts:
        bad += compare_labels(written, read_obj_labels(opts['--labels-decompressed']), 'qsp decompress\'s output',
                              exact=True)
    if '--decompressed' in opts:
        bad += compare_tex(written, read_obj_corner_values(opts['--decompressed'], 1),
                           'qsp decompress\'s output', exact=True)
    if '--tags-obj' in opts:
        bad += compare_tags(mesh, read_obj_tags(opts['--tags-obj']), 'the .obj', exact='--exact' in args)
    if '--tags-decompressed' in opts:   # the same numbering as this decoder's output (faces maybe moved)
        bad += compare_tags(written, read_obj_tags(opts['--tags-decompressed']), 'qsp decompress\'s output',
                            exact=True)
    if '--normals-obj' in opts:
        bad += compare_normals(mesh, read_obj_corner_values(opts['--normals-obj'], 2), 'the .obj',
                               exact='--exact' in args)
    if '--normals-decompressed' in opts:
        bad += compare_normals(written, read_obj_corner_values(opts['--normals-decompressed'], 2),
                               'qsp decompress\'s output', exact=True)
    if '--exact-obj' in opts:   # binary64 positions (exact positions section) against the mesh's text
        bad += qspexact.compare_exact(mesh, qspexact.read_mesh64(opts['--exact-obj']), 'the mesh', '--exact' in args)
        bad += qspexact.compare_encoder(open(path, 'rb').read(), g.sections(open(path, 'rb').read()),
                                          qspexact.exact_values(mesh))
    if '--exact-decompressed' in opts:
        bad += qspexact.compare_written(mesh, qspexact.read_mesh64(opts['--exact-decompressed']), 'qsp decompress\'s output')
    if '--values-obj' in opts:   # binary64 texture coordinates, normals, colours (exact values section)
        bad += qspvalues.compare_source(mesh, qspvalues.read_values64(opts['--values-obj']), '--exact' in args)
        bad += qspvalues.compare_encoder(mesh, g.sections(open(path, 'rb').read()))
    if '--values-decompressed' in opts:
        bad += qspvalues.compare_written(mesh, opts['--values-decompressed'])
    if '--stats' in args:
        print(' '.join('%s=%d' % kv for kv in sorted(list(STATS.items()) + list(qspcolors.STATS.items()))))
    if 'tex: unreferenced values not sorted (an encoder rule)' in STATS:
        bad.append('texture coordinates no corner names are not sorted by their bits, as the encoder writes them')
    if 'normals: unreferenced values not sorted (an encoder rule)' in STATS:
        bad.append('normals no corner names are not sorted by their bits, as the encoder writes them')
    for b in bad:
        print('%s: %s' % (path, b))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())
