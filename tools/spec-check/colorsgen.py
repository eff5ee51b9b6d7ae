#!/usr/bin/env python3
"""colorsgen.py: meshes with vertex and face colours, and colours sections (qsp_format.md "Colours
section", format 3.8) written from the text, to test qsppoly.py's decoder of that section
(qspcolors.py) against the meshes' own colours, against the reference encoder's bytes and against
`qsp decompress`.

usage: colorsgen.py --test [QSP]
       writes coloured meshes: OBJ `v x y z r g b [a]`; OFF `COFF` (three or four components) with
       face colours after a face's indices (one, three or four components) or face colours alone; PLY
       ascii and binary with uchar and float red, green, blue [, alpha] per vertex and per face; over
       polygen.py's polygon meshes, a grid of quads with a vertex in no face, a fan whose hub has more
       than eight neighbours, a grid with a hub in ten quads turned the other way (more than eight
       parallelograms across it); components of uchar integers, short decimals, float32 bits, float
       extremes (escapes, -0, subnormals, +-3e38), colour-map indices, smooth colours (where qsp
       compress must set flag bit 6, the parallelograms) and noisy ones (where it must not); lossless,
       with --keep-order and with --quantize-color (values halfway between grid points, values too
       large for the grid).
       Compresses each with QSP (default /work/main/build/qsp). Once QSP says it reads format 3.8
       (`QSP --version`), the files are QSP's own; before, they are `QSP compress --drop color`'s with
       the section the text's encoder writes put in (minor version 8), so the decoder is tested before
       the encoder exists. Checks, for each file:
       (a) qsppoly.py decodes it, and each vertex's and face's colour is the mesh's (float32 bits of
           its text, rounded to the binary grid of a --quantize-color mode) by position (index for
           index with --keep-order); once QSP reads 3.8, `QSP decompress` writes the same colours,
           positions and faces, index for index, as PLY (and OFF, and OBJ when only vertices have
           colours);
       (b) the section is byte for byte what qspcolors.encode_colors() writes for the mesh's colours
           (the text's encoder choices);
       A 201 x 201 grid of one RGBA colour: qsp compress's file must be one both decoders read, and
       the text's encoder's (flag bit 6 set and clear tie there: clear).
       (c) variants breaking each rule the text names (reserved flag bit 7, flag bit 6 with Kv = 0, Kv
           and Kf values, Kv = Kf = 0, modes, the 8192 * (stream bytes + 8) bound, a grid integer of
           2^40, images outside [0, 2^32), an infinity and a NaN, the section in a 3.7 file) are
           refused by qsppoly.py and, once it reads 3.8, by `QSP decompress`; sections with flag bit 6
           whose parallelograms leave the domain (means clamped) are read by both to the same colours;
           flag bit 6 toggled, truncations, a byte more and bit flips of the stream are refused by
           both or decoded by both to the same colours.
       Every vertex prediction rule (parallelograms 1, 2, more than 8; with flag bit 6 and none, the
       means and the previous vertex; without it, the same) must be met, and files with flag bit 6
       set and clear.
       Exit 0 if all hold, else 1.
       colorsgen.py --check FILE.qsp MESH [QSP]
       (a) and (b) for one file made from MESH (a golden file: index for index when its name holds
       keep_order), and (c) for its variants.
       colorsgen.py --mesh CASE OUT
       writes --test's mesh CASE (a name of CASES) to OUT, for a look at it.
"""
import math
import os
import random
import re
import struct
import subprocess
import sys
import tempfile

import qspcolors as c
import qspexact
import qspgeo as g
import qsppoly as poly

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, '..', '..'))
FAILED = []
NOTES = []


def expect(ok, what):
    if not ok:
        FAILED.append(what)
        print('colorsgen: ' + what, file=sys.stderr)
    return ok


def f32(text):
    """The binary32 a mesh reader gives a number's text (its binary64 rounded: the texts here are short)."""
    return g.f32_bits_of_double(float(text))


# ---------------- meshes ----------------
class Mesh:
    """Positions (texts), faces (0-based), vertex colours and face colours (tuples of texts, or None)."""

    def __init__(self, pos, faces):
        self.pos, self.faces = pos, faces
        self.vc = self.fc = None


def base_obj(path):
    pos, faces = [], []
    for line in open(path):
        w = line.split()
        if w[:1] == ['v']:
            pos.append(tuple(w[1:4]))
        elif w[:1] == ['f']:
            faces.append([int(t.split('/')[0]) - 1 for t in w[1:]])
    return Mesh(pos, faces)


def base_grid(n, m, spare=True):
    """An n x m grid of quads (z a bump), with a vertex in no face when spare."""
    pos = [('%d' % i, '%d' % j, '%.2f' % (0.3 * math.sin(i * 0.7) * math.cos(j * 0.5)))
           for j in range(m + 1) for i in range(n + 1)]
    faces = [[j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i]
             for j in range(m) for i in range(n)]
    if spare:
        pos.append(('9.5', '-3.25', '1'))
    return Mesh(pos, faces)


def base_fan():
    """A 7x7 grid of quads whose middle 3x3 cells are a fan of 12 triangles round a hub: the hub is in
    no quad, so it comes after the ring's vertices and has 12 decoded neighbours, of which 8 count."""
    n = 7
    pos = [('%d' % i, '%d' % j, '%.2f' % (0.2 * math.cos(i + j))) for j in range(n + 1) for i in range(n + 1)]
    at = lambda i, j: j * (n + 1) + i
    faces = [[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
             for j in range(n) for i in range(n) if not (2 <= i <= 4 and 2 <= j <= 4)]
    ring = [at(i, 2) for i in range(2, 5)] + [at(5, j) for j in range(2, 5)] + \
           [at(i, 5) for i in range(5, 2, -1)] + [at(2, j) for j in range(5, 2, -1)]
    hub = len(pos)
    pos.append(('3.5', '3.5', '0.75'))
    for i in range(len(ring)):
        faces.append([ring[i], ring[(i + 1) % len(ring)], hub])
    return Mesh(pos, faces)


def base_quad_fan():
    """A 9x9 grid of quads whose middle 5x5 cells are 10 quads round a hub, each two edges of the
    20-vertex ring and the hub, turned the other way from the grid's: the hub is then in no quad of
    the quad submesh, so it comes after the ring's vertices and has 10 parallelograms across it, of
    which 8 count."""
    n = 9
    pos = [('%d' % i, '%d' % j, '%.2f' % (0.2 * math.cos(i - j))) for j in range(n + 1) for i in range(n + 1)]
    at = lambda i, j: j * (n + 1) + i
    faces = [[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]
             for j in range(n) for i in range(n) if not (2 <= i <= 6 and 2 <= j <= 6)]
    ring = [at(i, 2) for i in range(2, 7)] + [at(7, j) for j in range(2, 7)] + \
           [at(i, 7) for i in range(7, 2, -1)] + [at(2, j) for j in range(7, 2, -1)]
    hub = len(pos)
    pos.append(('4.5', '4.5', '0.5'))
    for i in range(0, len(ring), 2):
        faces.append([hub, ring[(i + 2) % len(ring)], ring[i + 1], ring[i]])
    return Mesh(pos, faces)


EXTREMES = ['3e+38', '-3e+38', '3.4028235e+38', '1e-45', '-1e-45', '1e-38', '-0', '0', '1', '0.5', '-2.5']


def shortest32(u):
    """The shortest text that reads back to binary32 u (qsp refuses a colour text with more digits)."""
    for p in range(1, 10):
        t = '%.*g' % (p, g.bits_f32(u))
        if f32(t) == u:
            return t
    raise AssertionError(u)


def component(kind, rng, x, y, j):
    """A colour component's text: kind u8 (uchar, smooth over the positions), dec3, dec1, f32 (float32
    bits), extreme, idx (colour-map index), big (values of 2^30 among small ones), wide (4096 to 8192
    with 3 decimals: on the 2^-12 grid an integer of 25 bits, whose binary32 is not always on the
    grid), negzero (integers and -0, which no grid holds), half (odd multiples of 2^-9: halfway
    between points of the 2^-8 grid)."""
    s = 0.5 + 0.45 * math.sin(0.9 * x + 0.4 * y + 1.3 * j)
    if kind == 'u8':
        return '%d' % min(255, max(0, int(255 * s) + rng.randint(-3, 3)))
    if kind == 'dec3':
        return '%.3f' % min(1, max(0, s + rng.uniform(-0.01, 0.01)))
    if kind == 'dec1':
        return '%.1f' % (s * 4 - 1)
    if kind == 'f32':
        return shortest32(f32(repr(s + rng.uniform(-1e-3, 1e-3))))
    if kind == 'extreme':
        return rng.choice(EXTREMES)
    if kind == 'idx':
        return '%d' % rng.randint(0, 15)
    if kind == 'big':
        return '1073741824' if rng.random() < 0.1 else '%.4f' % s
    if kind == 'wide':
        return '%.3f' % (4096 + 4096 * s)
    if kind == 'negzero':
        return '-0' if rng.random() < 0.2 else '%d' % int(255 * s)
    if kind in ('smooth', 'smooth8'):   # no noise, slowly varying: the parallelograms predict it well
        t = 0.5 + 0.3 * math.sin(0.15 * x + 0.1 * y + j) + 0.1 * math.cos(0.12 * y - 0.05 * x)
        return '%.4f' % t if kind == 'smooth' else '%d' % round(255 * t)
    if kind == 'noisy':                 # the same with a camera's noise: the mean averages it
        t = 0.5 + 0.3 * math.sin(0.15 * x + 0.1 * y + j) + 0.1 * math.cos(0.12 * y - 0.05 * x)
        return '%d' % min(255, max(0, round(255 * t) + rng.randint(-40, 40)))
    if kind == 'half':
        return shortest32(f32(repr((2 * int(s * 256) + 1) / 512.0)))
    raise ValueError(kind)


def colour(mesh, vkinds, fkinds, seed):
    rng = random.Random(seed)
    num = lambda t: float(t)
    if vkinds:
        mesh.vc = [tuple(component(k, rng, num(p[0]), num(p[1]), j) for j, k in enumerate(vkinds)) for p in mesh.pos]
    if fkinds:
        mesh.fc = []
        for f in mesh.faces:
            x = sum(num(mesh.pos[v][0]) for v in f) / len(f)
            y = sum(num(mesh.pos[v][1]) for v in f) / len(f)
            mesh.fc.append(tuple(component(k, rng, x, y, j) for j, k in enumerate(fkinds)))
    return mesh


def ply_type(texts):
    return 'uchar' if all(re.fullmatch(r'\d+', t) and int(t) <= 255 for t in texts) else 'float'


NAMES = ('red', 'green', 'blue', 'alpha')


def write(mesh, path, fmt):
    """fmt: obj, off, ply-ascii or ply-binary."""
    if fmt == 'obj':
        with open(path, 'w') as o:
            for i, p in enumerate(mesh.pos):
                o.write('v %s%s\n' % (' '.join(p), ' ' + ' '.join(mesh.vc[i]) if mesh.vc else ''))
            for f in mesh.faces:
                o.write('f %s\n' % ' '.join(str(v + 1) for v in f))
        return
    if fmt == 'off':
        with open(path, 'w') as o:
            o.write('%s\n%d %d 0\n' % ('COFF' if mesh.vc else 'OFF', len(mesh.pos), len(mesh.faces)))
            for i, p in enumerate(mesh.pos):
                o.write('%s%s\n' % (' '.join(p), ' ' + ' '.join(mesh.vc[i]) if mesh.vc else ''))
            for k, f in enumerate(mesh.faces):
                o.write('%d %s%s\n' % (len(f), ' '.join(map(str, f)), ' ' + ' '.join(mesh.fc[k]) if mesh.fc else ''))
        return
    binary = fmt == 'ply-binary'
    vt = [ply_type([v[j] for v in mesh.vc]) for j in range(len(mesh.vc[0]))] if mesh.vc else []
    ft = [ply_type([f[j] for f in mesh.fc]) for j in range(len(mesh.fc[0]))] if mesh.fc else []
    head = ['ply', 'format %s 1.0' % ('binary_little_endian' if binary else 'ascii'),
            'element vertex %d' % len(mesh.pos), 'property float x', 'property float y', 'property float z']
    head += ['property %s %s' % (t, NAMES[j]) for j, t in enumerate(vt)]
    head += ['element face %d' % len(mesh.faces), 'property list uchar int vertex_indices']
    head += ['property %s %s' % (t, NAMES[j]) for j, t in enumerate(ft)]
    head.append('end_header')
    out = bytearray(('\n'.join(head) + '\n').encode())

    def one(t, text):
        if not binary:
            return text
        return struct.pack('<B', int(text)) if t == 'uchar' else struct.pack('<f', float(text))

    for i, p in enumerate(mesh.pos):
        row = [one('float', t) for t in p] + ([one(t, x) for t, x in zip(vt, mesh.vc[i])] if mesh.vc else [])
        out += b''.join(row) if binary else (' '.join(row) + '\n').encode()
    for k, f in enumerate(mesh.faces):
        if binary:
            out += struct.pack('<B%di' % len(f), len(f), *f)
            out += b''.join(one(t, x) for t, x in zip(ft, mesh.fc[k])) if mesh.fc else b''
        else:
            out += ('%d %s%s\n' % (len(f), ' '.join(map(str, f)), ' ' + ' '.join(mesh.fc[k]) if mesh.fc else '')).encode()
    open(path, 'wb').write(bytes(out))


# ---------------- reading meshes back (the source, and what qsp decompress writes) ----------------
PLY_TYPES = {b'char': 'b', b'int8': 'b', b'uchar': 'B', b'uint8': 'B', b'short': 'h', b'int16': 'h',
             b'ushort': 'H', b'uint16': 'H', b'int': 'i', b'int32': 'i', b'uint': 'I', b'uint32': 'I',
             b'float': 'f', b'float32': 'f', b'double': 'd', b'float64': 'd'}
VERTEX_NOT_COLOUR = {b'x', b'y', b'z', b'nx', b'ny', b'nz', b'u', b'v', b's', b't', b'texture_u', b'texture_v'}


def read_colored(path):
    """(positions as binary32 bits, faces, vertex colours, face colours, notes) of an OBJ, OFF or PLY
    file, colours as tuples of binary32 bits (None when there are none); notes: the PLY colour
    properties' types."""
    data = open(path, 'rb').read()
    if data.startswith(b'ply'):
        return read_ply(data)
    text = data.decode()
    lines = [ln.split('#')[0].split() for ln in text.split('\n')]
    lines = [w for w in lines if w]
    if lines and lines[0][0].endswith('OFF'):
        head = lines[0][0]
        rest = lines[0][1:] or lines[1]
        body = lines[1:] if lines[0][1:] else lines[2:]
        nv, nf = int(rest[0]), int(rest[1])
        pos, vc, faces, fc = [], [], [], []
        for w in body[:nv]:
            pos.append(tuple(f32(t) for t in w[:3]))
            vc.append(tuple(f32(t) for t in w[3:]))
        for w in body[nv:nv + nf]:
            d = int(w[0])
            faces.append([int(t) for t in w[1:1 + d]])
            fc.append(tuple(f32(t) for t in w[1 + d:]))
        vc = vc if 'C' in head and any(vc) else None
        fc = fc if any(fc) else None
        return pos, faces, vc, fc, []
    pos, vc, faces = [], [], []
    for w in lines:
        if w[0] == 'v':
            pos.append(tuple(f32(t) for t in w[1:4]))
            vc.append(tuple(f32(t) for t in w[4:]))
        elif w[0] == 'f':
            idx = [int(t.split('/')[0]) for t in w[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
    return pos, faces, (vc if any(vc) else None), None, []


def read_ply(data):
    elements, fmt, end = qspexact.ply_header(data)
    assert fmt in (b'ascii', b'binary_little_endian', b'binary_big_endian'), fmt
    endian = '>' if fmt == b'binary_big_endian' else '<'
    words = data[end:].split() if fmt == b'ascii' else None
    at, wi = end, 0

    def one(t):
        nonlocal at, wi
        if words is not None:
            wi += 1
            return float(words[wi - 1]) if PLY_TYPES[t] in 'fd' else int(words[wi - 1])
        ch = PLY_TYPES[t]
        v = struct.unpack_from(endian + ch, data, at)[0]
        at += struct.calcsize(ch)
        return v

    pos, faces, vc, fc, notes = [], [], [], [], []
    for name, n, props in elements:
        colour_props = [(p, t) for p, t in props if t[0] != b'list' and (name != b'vertex' or p not in VERTEX_NOT_COLOUR)]
        if colour_props and name in (b'vertex', b'face'):
            notes.append('%s %s' % (name.decode(), ' '.join('%s %s' % (t[0].decode(), p.decode()) for p, t in colour_props)))
        for _ in range(n):
            row, col = {}, []
            for pname, ptype in props:
                if ptype[0] == b'list':
                    k = int(one(ptype[1]))
                    row[pname] = [int(one(ptype[2])) for _ in range(k)]
                else:
                    row[pname] = one(ptype[0])
                    if (pname, ptype) in colour_props:
                        col.append(g.f32_bits_of_double(float(row[pname])))
            if name == b'vertex':
                pos.append(tuple(g.f32_bits_of_double(float(row[k])) for k in (b'x', b'y', b'z')))
                vc.append(tuple(col))
            elif name == b'face':
                faces.append(row.get(b'vertex_indices', row.get(b'vertex_index')))
                fc.append(tuple(col))
    return pos, faces, (vc if any(vc) else None), (fc if any(fc) else None), notes


# ---------------- files ----------------
def reseal(data, secs, minor=None):
    return g.container(data[:9] + bytes([data[9] if minor is None else minor]) + data[10:11], secs)


def canonical(data):
    """(positions, faces, order) of the output mesh before an order section; order None or (cv, of)."""
    secs = g.sections(data)
    pos, faces, _ = poly.canonical_mesh(data, secs)
    order = poly.decode_order(secs[0x04], len(pos), [len(f) for f in faces]) if 0x04 in secs else None
    return pos, faces, order


def cycle_key(cyc):
    k = min(range(len(cyc)), key=lambda i: cyc[i:] + cyc[:i])
    return tuple(cyc[k:] + cyc[:k])


def to_canonical(pos, faces, order, spos, sfaces, svc, sfc):
    """The source's colours in the output's order before an order section: through the order section
    when there is one, else by each vertex's position and each face's corner positions (distinct in
    these meshes). None where a vertex or face is not found."""
    vc = fc = None
    if order:
        cv, of = order
        if svc:
            vc = [None] * len(pos)
            for j, cc in enumerate(cv):
                vc[cc] = svc[j]
        if sfc:
            fc = [None] * len(faces)
            for f, (cc, _) in enumerate(of):
                fc[cc] = sfc[f]
        return vc, fc
    if svc:
        by = {}
        for p, col in zip(spos, svc):
            by.setdefault(p, []).append(col)
        vc = [by[p][0] if len(by.get(p, [])) == 1 else None for p in pos]
    if sfc:
        by = {}
        for f, col in zip(sfaces, sfc):
            by.setdefault(cycle_key([spos[v] for v in f]), []).append(col)
        fc = [None] * len(faces)
        for i, f in enumerate(faces):
            got = by.get(cycle_key([pos[v] for v in f]), [])
            fc[i] = got[0] if len(got) == 1 else None
    return vc, fc


def put(base, src, quantize):
    """base (the mesh compressed with --drop color) with the section the text's encoder writes for the
    mesh src's colours, at minor version 8."""
    spos, sfaces, svc, sfc, _ = read_colored(src)
    pos, faces, order = canonical(base)
    vc, fc = to_canonical(pos, faces, order, spos, sfaces, svc, sfc)
    assert not vc or None not in vc, 'a vertex not found by its position'
    assert not fc or None not in fc, 'a face not found by its corners'
    secs = g.sections(base)
    secs[0x0b] = c.encode_colors(vc, fc, len(pos), faces, quantize)
    return reseal(base, secs, 8)


def reads_38(qsp):
    m = re.search(r'reads 3\.0 to 3\.(\d+)', subprocess.run([qsp, '--version'], capture_output=True,
                                                             text=True).stdout)
    return bool(m) and int(m.group(1)) >= 8


def quantize_of(modes):
    """The --quantize-color BITS a section's modes show (every binary grid mode is 16 + BITS)."""
    bins = {m - 16 for m in modes if m >= 17}
    return bins.pop() if len(bins) == 1 else None if not bins else -1


# ---------------- (a) and (b) ----------------
TIE = 'colors: encoder: parallelograms as large (a tie)'



def check_file(name, data, src, exact, qsp, tmp, live):
    """Checks (a) and (b) of one file made from the mesh src; returns the decoded mesh (or None)."""
    try:
        mesh = poly.decode_file(data)
    except g.FormatError as e:
        expect(False, '%s: qsppoly.py refuses it: %s' % (name, e))
        return None
    cols = mesh[9]
    if not expect(cols is not None, '%s: no colours section' % name):
        return None
    modes = cols['modes']
    spos, sfaces, svc, sfc, _ = read_colored(src)
    Kv = len(svc[0]) if svc else 0
    expect(len(modes) == Kv + (len(sfc[0]) if sfc else 0),
           '%s: %d components, the mesh has %d per vertex and %s per face' % (name, len(modes), Kv, len(sfc[0]) if sfc else 0))
    want_v = c.rounded(svc, modes[:Kv]) if svc else None
    want_f = c.rounded(sfc, modes[Kv:]) if sfc else None
    quantized_geo = mesh[3]
    if exact:
        expect(cols['vertex'] == want_v, '%s: vertex colours differ from the mesh\'s, index for index (first: %s)' % (
            name, first_diff(cols['vertex'], want_v)))
        expect(cols['face'] == want_f, '%s: face colours differ from the mesh\'s, index for index (first: %s)' % (
            name, first_diff(cols['face'], want_f)))
        if not quantized_geo:
            expect(mesh[0] == spos, '%s: positions differ from the mesh\'s' % name)
    elif quantized_geo:   # positions moved: the colours as multisets only
        for what, mine, theirs in (('vertex', cols['vertex'], want_v), ('face', cols['face'], want_f)):
            expect(sorted(mine or []) == sorted(theirs or []) and (mine is None) == (theirs is None),
                   '%s: %s colours differ from the mesh\'s as a multiset' % (name, what))
        NOTES.append('%s: quantized positions: colours compared as multisets, the encoder\'s bytes not compared' % name)
        if live:
            compare_decompressed(name, data, mesh, qsp, tmp)
        return mesh
    else:
        pos = mesh[0]
        if cols['vertex'] is not None or want_v is not None:
            mine = sorted(zip(pos, cols['vertex'] or [None] * len(pos)), key=repr)
            theirs = sorted(zip(spos, want_v or [None] * len(spos)), key=repr)
            expect(mine == theirs, '%s: vertex colours by position differ from the mesh\'s (first: %s)' % (
                name, first_diff(mine, theirs)))
        if cols['face'] is not None or want_f is not None:
            mine = sorted(((cycle_key([pos[v] for v in f]), col) for f, col in zip(mesh[1], cols['face'] or [None] * len(mesh[1]))), key=repr)
            theirs = sorted(((cycle_key([spos[v] for v in f]), col) for f, col in zip(sfaces, want_f or [None] * len(sfaces))), key=repr)
            expect(mine == theirs, '%s: face colours by corner positions differ from the mesh\'s (first: %s)' % (
                name, first_diff(mine, theirs)))
    # (b) the text's encoder choices, byte for byte
    secs = g.sections(data)
    pos, faces, order = canonical(data)
    vc, fc = to_canonical(pos, faces, order, spos, sfaces, svc, sfc)
    if (vc and None in vc) or (fc and None in fc):
        NOTES.append('%s: the encoder\'s bytes not compared (positions not distinct)' % name)
    else:
        q = quantize_of(modes)
        if q == -1:
            expect(False, '%s: binary grid modes of different steps %s' % (name, modes))
        else:
            ties = c.STATS.get(TIE, 0)
            mine = c.encode_colors(vc, fc, len(pos), faces, q)
            theirs = bytes(secs[0x0b])
            if c.STATS.get(TIE, 0) > ties:
                NOTES.append('%s: flag bit 6 set and clear give sections of one size: the file has it %s' % (
                    name, 'set' if theirs[0] & 0x40 else 'clear'))
            if mine != theirs:
                at = next((i for i in range(min(len(mine), len(theirs))) if mine[i] != theirs[i]), min(len(mine), len(theirs)))
                expect(False, '%s: the section (%d bytes, flags 0x%02x, modes %s) is not the text\'s encoder\'s (%d bytes, '
                       'flags 0x%02x, modes %s): first difference at payload byte %d' % (
                           name, len(theirs), theirs[0], list(theirs[1:1 + len(modes)]), len(mine), mine[0],
                           list(mine[1:1 + len(c.parse_header(mine, len(pos), len(faces))[2])]), at))
    if live:
        compare_decompressed(name, data, mesh, qsp, tmp)
    return mesh


def first_diff(a, b):
    if a is None or b is None:
        return '%s against %s' % ('none' if a is None else len(a), 'none' if b is None else len(b))
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            return 'at %d: %r, there %r' % (i, x, y)
    return 'the counts %d and %d' % (len(a), len(b))


def written_types_ok(notes, cols, Kv):
    """The text's PLY writer rule: colours whose values are all integers 0..255 uchar, others float."""
    bad = []
    for note in notes:
        words = note.split()
        which, types = words[0], words[1::2]
        vals = cols['vertex'] if which == 'vertex' else cols['face']
        if not vals:
            continue
        ints = all(g.bits_f32(u) == int(g.bits_f32(u)) and 0 <= g.bits_f32(u) <= 255 and u != 0x80000000
                   for col in vals for u in col)
        if ints and any(t != 'uchar' for t in types):
            bad.append('%s colours all integers 0..255, written as %s' % (which, ' '.join(types)))
        if not ints and all(t == 'uchar' for t in types):
            bad.append('%s colours not all integers 0..255, written as uchar' % which)
    return bad


def compare_decompressed(name, data, mesh, qsp, tmp):
    """qsp decompress FILE to PLY and OFF (and OBJ for vertex colours alone) against this decoder's
    mesh, index for index."""
    f = os.path.join(tmp, name + '.qsp')
    open(f, 'wb').write(data)
    cols = mesh[9]
    Kv = len(cols['vertex'][0]) if cols['vertex'] else 0
    outs = ['off'] + (['obj'] if not cols['face'] else [])   # (qsp decompress writes no PLY)
    for ext in outs:
        out = os.path.join(tmp, '%s.out.%s' % (name, ext))
        r = subprocess.run([qsp, 'decompress', '-f', f, '-o', out], capture_output=True)
        if not expect(r.returncode == 0, '%s: qsp decompress -o .%s refuses it: %s' % (name, ext, r.stderr.decode().strip())):
            continue
        pos, faces, vc, fc, notes = read_colored(out)
        what = 'qsp decompress\'s .%s' % ext
        if not mesh[3]:
            expect(pos == mesh[0], '%s: %s positions differ from qsppoly.py\'s' % (name, what))
        expect(faces == mesh[1], '%s: %s faces differ from qsppoly.py\'s' % (name, what))
        expect(vc == cols['vertex'], '%s: %s vertex colours differ from qsppoly.py\'s (first: %s)' % (
            name, what, first_diff(vc, cols['vertex'])))
        expect(fc == cols['face'], '%s: %s face colours differ from qsppoly.py\'s (first: %s)' % (
            name, what, first_diff(fc, cols['face'])))
        if ext == 'ply':
            for b in written_types_ok(notes, cols, Kv):
                expect(False, '%s: %s: %s' % (name, what, b))


# ---------------- (c) ----------------
def variants(data):
    """(what, file bytes, must be refused) of the file's colours section broken."""
    secs = g.sections(data)
    p = bytes(secs[0x0b])
    pos, faces, _ = canonical(data)
    V, F = len(pos), len(faces)
    Kv, Kf, modes, stream, pg = c.parse_header(p, V, F)
    out = []

    def add(what, payload, refused=True, minor=None):
        s = dict(secs)
        s[0x0b] = payload
        out.append((what, reseal(data, s, minor), refused))

    add('reserved flag bit 7', bytes([p[0] | 0x80]) + p[1:])
    # flag bit 6 with Kv = 0: a section of face colours alone (the file's Kf, else 1), valid without it
    kf = Kf or 1
    faces_only = c.pack(0, kf, [1] * kf, [0] * (F * kf), V, faces)
    add('face colours alone (Kv = 0), flag bit 6 clear', faces_only, refused=False)
    add('face colours alone (Kv = 0), flag bit 6 (parallelograms) set', bytes([faces_only[0] | 0x40]) + faces_only[1:])
    if Kv:   # the other predictions: other colours (or a value out of its range), alike in both decoders
        add('flag bit 6 (parallelograms) %s' % ('cleared' if pg else 'set'), bytes([p[0] ^ 0x40]) + p[1:], refused=None)
    for k in (1, 2, 5, 6, 7):
        add('Kv = %d' % k, bytes([p[0] & ~7 | k]) + p[1:])
    for k in (2, 5, 6, 7):
        add('Kf = %d' % k, bytes([p[0] & ~0x38 | k << 3]) + p[1:])
    add('Kv = Kf = 0', bytes([0]) + p[1:])
    for m in (11, 15, 16, 41, 64, 255):
        add('component 0 mode %d' % m, p[:1] + bytes([m]) + p[2:])
    add('the section in a 3.7 file', p, minor=7)
    add('the section ending in its modes', p[:Kv + Kf])
    # the bound: every stream byte gone but what V * Kv + F * Kf still allows
    n = V * Kv + F * Kf
    cut = -(-n // 8192) - 8 - 1          # stream bytes for which n > 8192 * (bytes + 8)
    if 0 <= cut < len(stream):
        add('%d components in a stream cut to %d bytes (above 8192 * (bytes + 8))' % (n, cut), p[:1 + Kv + Kf] + stream[:cut])
    # crafted residuals: the first component of vertex 0 (or face 0) out of its range
    for what, m, r in (('a grid integer of 2^40', 1, 1 << 40), ('a grid integer of -2^40', 1, -(1 << 40)),
                       ('a float image of -1', 0, -c.FLOAT_ZERO - 1), ('a float image of 2^32', 0, 1 << 31),
                       ('+infinity', 0, g.image(0x7F800000) - c.FLOAT_ZERO),
                       ('-infinity', 0, g.image(0xFF800000) - c.FLOAT_ZERO),
                       ('a NaN', 0, g.image(0x7FC00000) - c.FLOAT_ZERO)):
        ms = [m] * (Kv + Kf)
        res = [0] * (V * Kv + F * Kf)
        res[0] = r
        add('every mode %s, %s first' % (c.mode_name(m), what), c.pack(Kv, Kf, ms, res, V, faces))
    # 2^40 - 1, whose binary32 is 2^40: the second vertex (or face) predicted from the first with a
    # residual 0 is 2^40 if "the integer" is the decoded value's (qspcolors.INTEGER_OF_DECODED), 2^40 - 1
    # if it is the coded q
    ms = [1] * (Kv + Kf)
    res = [0] * (V * Kv + F * Kf)
    res[0] = (1 << 40) - 1
    add('every mode dec0, a grid integer of 2^40 - 1 first (its binary32 is 2^40), the next one predicted '
        'from it with residual 0', c.pack(Kv, Kf, ms, res, V, faces), refused=None)
    # the same in dec9, a third integer coded as residual 5 - (2^40 - 1): 5 (a value 5e-9) if the
    # prediction is the coded q, 5 + I - (2^40 - 1) (about -3.1e-5) if it is the integer I of the first
    # value's binary32; refused by neither
    ms = [10] * (Kv + Kf)
    res = [0] * (V * Kv + F * Kf)
    K = Kv or Kf
    res[0], res[K], res[2 * K] = (1 << 40) - 1, 0, 5 - ((1 << 40) - 1)
    if (Kv and V >= 3) or (not Kv and F >= 3):
        add('every mode dec9, a grid integer of 2^40 - 1 first, the next ones predicted from it with residuals 0 '
            'and 5 - (2^40 - 1)', c.pack(Kv, Kf, ms, res, V, faces), refused=None)
    # flag bit 6, parallelograms a + b - o leaving the domain (the mean clamped): vertex colours of
    # extreme values (dec0: -B, 0, B with B = 2^40 - 2^16, held by binary32; float bits: -+3.4028235e38,
    # whose images 0x00800000 and 0xff7fffff give a + b - o below 0 and above 2^32 - 1), face colours 0
    if Kv:
        crng = random.Random(V)
        B = float((1 << 40) - (1 << 16))
        for what, m, vals in (('dec0', 1, (-B, 0.0, B)), ('float', 0, (-3.4028235e38, 3.4028235e38))):
            vc = [tuple(g.f32_bits_of_double(crng.choice(vals)) for _ in range(Kv)) for _ in range(V)]
            fc = [(g.f32_bits_of_double(0.0),) * Kf] * F if Kf else None
            clamped = c.STATS.get('colors: mean clamped', 0)
            q = c.encode_colors(vc, fc, V, faces, modes=[m] * Kv + [1] * Kf, pg=True)
            try:
                got = c.decode_colors(q, V, F, faces)[0]
            except g.FormatError as e:
                got = str(e)
            expect(got == vc, 'the text\'s encoder and decoder disagree on vertex colours of extremes in %s with '
                   'parallelograms: %s' % (what, got if isinstance(got, str) else first_diff(got, vc)))
            add('flag bit 6, vertex colours %s of extremes (%d means clamped)' % (
                what, (c.STATS.get('colors: mean clamped', 0) - clamped) // 2), q, refused=False)
    # the stream's end; bit flips: refused, or decoded to other colours alike by both decoders
    add('the stream a byte short', p[:-1], refused=None)
    add('a zero byte after the stream', p + b'\x00')
    add('a byte 0x01 after the stream', p + b'\x01', refused=None)
    add('no stream', p[:1 + Kv + Kf], refused=None)
    rng = random.Random(len(p))
    at = list(range(len(stream)))
    rng.shuffle(at)
    for i in sorted(at[:24]):
        b = rng.randrange(8)
        q = bytearray(p)
        q[1 + Kv + Kf + i] ^= 1 << b
        add('stream byte %d bit %d flipped' % (i, b), bytes(q), refused=None)
    return out


def check_variants(name, data, qsp, tmp, live):
    pos, faces, _ = canonical(data)
    done = 0
    for i, (what, bad, refused) in enumerate(variants(data)):
        what = '%s: %s' % (name, what)
        try:
            got = poly.decode_file(bad)[9] if 'a 3.7 file' in what else dict(zip(
                ('vertex', 'face', 'modes'), c.decode_colors(g.sections(bad)[0x0b], len(pos), len(faces), faces, bad[9])))
            why = None
        except g.FormatError as e:
            got, why = None, str(e)
        if refused is True:
            expect(why is not None, 'qsppoly.py does not refuse %s' % what)
        elif refused is False:
            expect(why is None, 'qsppoly.py refuses %s: %s' % (what, why))
        done += 1
        if not live:
            continue
        f, out = os.path.join(tmp, 'variant.qsp'), os.path.join(tmp, 'variant.off')
        open(f, 'wb').write(bad)
        r = subprocess.run([qsp, 'decompress', '-f', f, '-o', out], capture_output=True)
        if refused is True:
            expect(r.returncode != 0, 'qsp decompress does not refuse %s' % what)
        elif refused is False:
            expect(r.returncode == 0, 'qsp decompress refuses %s: %s' % (what, r.stderr.decode().strip()))
        else:
            expect((r.returncode != 0) == (why is not None), '%s: qsppoly.py %s, qsp decompress %s' % (
                what, 'refuses it (%s)' % why if why else 'decodes it', 'refuses it (%s)' % r.stderr.decode().strip()
                if r.returncode else 'decodes it'))
        if r.returncode == 0 and got is not None:
            mesh = poly.decode_file(bad)
            _, _, vc, fc, _ = read_colored(out)
            expect(vc == mesh[9]['vertex'] and fc == mesh[9]['face'],
                   '%s: qsp decompress and qsppoly.py decode it to other colours%s' % (
                       what, ' (qsp decompress writes none)' if vc is None and fc is None else ''))
    return done


# ---------------- --test ----------------
CASES = [   # name, base mesh, format, vertex component kinds, face component kinds, qsp compress options
    ('poly1_obj_rgb_dec3', 'poly1', 'obj', ('dec3',) * 3, None, []),
    ('poly2_obj_rgba_f32', 'poly2', 'obj', ('f32', 'f32', 'f32', 'dec1'), None, []),
    ('poly3_obj_rgb_extreme', 'poly3', 'obj', ('u8', 'dec1', 'extreme'), None, []),
    ('poly1_coff_rgba_u8_face_idx', 'poly1', 'off', ('u8',) * 4, ('idx',), []),
    ('poly2_off_face_rgb_dec3', 'poly2', 'off', None, ('dec3',) * 3, []),
    ('poly3_coff_rgba_dec3_face_u8_keep_order', 'poly3', 'off', ('dec3',) * 4, ('u8',) * 4, ['--keep-order']),
    ('grid_coff_rgb_dec1', 'grid', 'off', ('dec1',) * 3, None, []),
    ('poly1_ply_ascii_u8', 'poly1', 'ply-ascii', ('u8',) * 3, ('u8',) * 4, []),
    ('poly2_ply_binary_float', 'poly2', 'ply-binary', ('f32',) * 4, ('f32',) * 3, []),
    ('poly3_ply_binary_u8_keep_order', 'poly3', 'ply-binary', ('u8',) * 4, None, ['--keep-order']),
    ('grid_ply_ascii_face_float', 'grid', 'ply-ascii', None, ('extreme', 'f32', 'dec3', 'u8'), []),
    ('poly2_obj_q8', 'poly2', 'obj', ('f32', 'f32', 'half', 'f32'), None, ['--quantize-color', '8']),
    ('poly1_ply_binary_q12_big', 'poly1', 'ply-binary', ('f32', 'big', 'f32'), ('f32', 'dec3', 'half'), ['--quantize-color', '12']),
    ('poly3_coff_q6_keep_order', 'poly3', 'off', ('dec3',) * 3, ('dec3',) * 3, ['--quantize-color', '6', '--keep-order']),
    ('fan_obj_rgb_u8', 'fan', 'obj', ('u8',) * 3, None, []),
    ('grid_obj_rgb_negzero', 'grid', 'obj', ('u8', 'negzero', 'dec1'), None, []),
    ('grid_obj_rgb_wide_q12', 'grid', 'obj', ('wide', 'dec3', 'u8'), None, ['--quantize-color', '12']),
    ('poly1_obj_rgb_q24', 'poly1', 'obj', ('f32', 'dec3', 'u8'), None, ['--quantize-color', '24']),
    ('poly2_coff_q1_face', 'poly2', 'off', ('dec1', 'f32', 'half', 'u8'), ('dec3', 'extreme', 'u8'), ['--quantize-color', '1']),
    ('fan_ply_binary_face_q10_keep_order', 'fan', 'ply-binary', ('f32',) * 3, ('u8',) * 3, ['--quantize', '10', '--keep-order']),
    # flag bit 6: smooth colours, where the parallelograms must win, and noisy ones, where the means must
    ('grid24_obj_rgb_smooth', 'grid24', 'obj', ('smooth',) * 3, None, []),
    ('grid24_ply_binary_rgba_smooth8_face_u8', 'grid24', 'ply-binary', ('smooth8',) * 4, ('u8',) * 3, []),
    ('grid24_ply_binary_rgb_noisy', 'grid24', 'ply-binary', ('noisy',) * 3, None, []),
    ('grid24_coff_rgb_noisy_keep_order', 'grid24', 'off', ('noisy',) * 3, ('u8',) * 3, ['--keep-order']),
    ('quadfan_obj_rgb_smooth', 'quadfan', 'obj', ('smooth',) * 3, None, []),
    ('quadfan_ply_binary_rgb_smooth8_q8', 'quadfan', 'ply-binary', ('smooth8',) * 3, None, ['--quantize-color', '8']),
]
# the flag bit 6 qsp compress must choose (the text's encoder's choice is checked for every file)
WANT_PG = {'grid24_obj_rgb_smooth': True, 'grid24_ply_binary_rgba_smooth8_face_u8': True,
           'grid24_ply_binary_rgb_noisy': False, 'grid24_coff_rgb_noisy_keep_order': False,
           'quadfan_obj_rgb_smooth': True}


def base_mesh(kind, tmp):
    if kind.startswith('poly'):
        obj = os.path.join(tmp, kind + '.obj')
        if not os.path.exists(obj):
            subprocess.run([sys.executable, os.path.join(HERE, 'polygen.py'), obj, kind[4:]], check=True)
        return base_obj(obj)
    if kind == 'grid':
        return base_grid(6, 5)
    if kind == 'fan':
        return base_fan()
    if kind == 'grid24':
        return base_grid(24, 24)
    if kind == 'quadfan':
        return base_quad_fan()
    raise ValueError(kind)


def make(case, tmp):
    name, base, fmt, vk, fk, opts = case
    mesh = colour(base_mesh(base, tmp), vk, fk, seed=len(name))
    path = os.path.join(tmp, name + {'obj': '.obj', 'off': '.off'}.get(fmt, '.ply'))
    write(mesh, path, fmt)
    return path


def compress(qsp, src, out, opts, live, tmp):
    """The file of src: qsp's own when live, else --drop color's with the text's section put in."""
    if live:
        r = subprocess.run([qsp, 'compress', '-f', '-q'] + opts + [src, out], capture_output=True)
        if not expect(r.returncode == 0, 'qsp compress refuses %s: %s' % (src, r.stderr.decode().strip())):
            return None
        return open(out, 'rb').read()
    q = None
    rest = list(opts)
    if '--quantize-color' in rest:
        i = rest.index('--quantize-color')
        q = int(rest[i + 1])
        del rest[i:i + 2]
    base = out[:-len('.qsp')] + '.base.qsp'
    r = subprocess.run([qsp, 'compress', '-f', '-q', '--drop', 'color'] + rest + [src, base], capture_output=True)
    if not expect(r.returncode == 0, 'qsp compress --drop color refuses %s: %s' % (src, r.stderr.decode().strip())):
        return None
    return put(open(base, 'rb').read(), src, q)


def bound_case(qsp, tmp, live):
    """A 150 x 150 grid with vertex colours: V * Kv = 68403 components, more than 8192 * 8, so the
    stream cut to nothing breaks the bound (checked on the layout's faces alone: no geometry decode)."""
    mesh = colour(base_grid(150, 150, spare=False), ('u8',) * 3, None, 3)
    mesh.vc = [('10', '20', '30')] * len(mesh.pos)
    src = os.path.join(tmp, 'bound.obj')
    write(mesh, src, 'obj')
    data = compress(qsp, src, os.path.join(tmp, 'bound.qsp'), [], live, tmp)
    if data is None:
        return
    secs = g.sections(data)
    V, F, C, U = g.counts(secs[1])
    _, quads = poly.layout(secs[2], C, U)
    faces = [list(q) for q in quads]
    p = bytes(secs[0x0b])
    vc, fc, modes = c.decode_colors(p, V, F, faces)
    expect(vc == [tuple(f32(t) for t in ('10', '20', '30'))] * V, 'bound grid: other colours')
    n = V * 3
    for cut in (0,):
        bad = p[:4] + p[4:4 + cut]
        ok = n <= 8192 * (cut + 8)
        try:
            c.decode_colors(bad, V, F, faces)
            refused = None
        except g.FormatError as e:
            refused = str(e)
        if not ok:
            expect(refused is not None and '8192' in refused,
                   'bound grid: %d components in a %d-byte stream not refused by the bound (%s)' % (n, cut, refused))
        if live:
            s = dict(secs)
            s[0x0b] = bad
            f = os.path.join(tmp, 'bound_cut.qsp')
            open(f, 'wb').write(reseal(data, s))
            r = subprocess.run([qsp, 'decompress', '-f', f, '-o', f + '.off'], capture_output=True)
            expect(r.returncode != 0, 'qsp decompress does not refuse %d components in a %d-byte stream' % (n, cut))


def constant_case(qsp, tmp, live):
    """A 201 x 201 grid whose vertices all have the colour 255 255 255 255 (PLY uchar): the file qsp
    compress writes must be one both decoders read. Its stream is tiny (161604 components whose
    residuals are all 0), which the 8192 * (stream bytes + 8) bound must still allow."""
    if not live:
        return
    mesh = base_grid(200, 200, spare=False)
    mesh.vc = [('255',) * 4] * len(mesh.pos)
    src = os.path.join(tmp, 'constant.ply')
    write(mesh, src, 'ply-binary')
    data = compress(qsp, src, os.path.join(tmp, 'constant.qsp'), [], live, tmp)
    if data is None:
        return
    secs = g.sections(data)
    V, F, C, U = g.counts(secs[1])
    _, quads = poly.layout(secs[2], C, U)
    try:
        vc, _, _ = c.decode_colors(bytes(secs[0x0b]), V, F, [list(q) for q in quads])
        expect(vc == [(f32('255'),) * 4] * V, 'constant grid: qsppoly.py decodes other colours')
    except g.FormatError as e:
        expect(False, 'constant grid (%d vertices, one RGBA colour): qsppoly.py refuses the file qsp compress '
               'wrote: %s' % (V, e))
    # every residual 0 with either prediction: flag bit 6 set and clear give sections of one size, and
    # the encoder keeps the clear one
    ties = c.STATS.get(TIE, 0)
    mine = c.encode_colors([(f32('255'),) * 4] * V, None, V, [list(q) for q in quads])
    theirs = bytes(secs[0x0b])
    expect(mine == theirs, 'constant grid: the section (%d bytes, flags 0x%02x) is not the text\'s encoder\'s '
           '(%d bytes, flags 0x%02x)' % (len(theirs), theirs[0], len(mine), mine[0]))
    if c.STATS.get(TIE, 0) > ties:
        NOTES.append('constant grid: flag bit 6 set and clear give sections of one size: the file has it %s' % (
            'set' if theirs[0] & 0x40 else 'clear'))
    f = os.path.join(tmp, 'constant.qsp')
    r = subprocess.run([qsp, 'decompress', '-f', f, '-o', f + '.off'], capture_output=True)
    expect(r.returncode == 0, 'constant grid: qsp decompress refuses the file qsp compress wrote: %s' % (
        r.stderr.decode().strip()))


def test(qsp, tmp):
    live = bool(qsp) and reads_38(qsp)
    if qsp and not live:
        print('colorsgen: %s does not read format 3.8 yet: its files get the text\'s section put in, and '
              'qsp decompress is not asked' % qsp)
    n = 0
    pg_files = {True: [], False: []}    # the files with vertex colours, by flag bit 6
    for case in CASES:
        name, opts = case[0], case[5]
        src = make(case, tmp)
        data = compress(qsp, src, os.path.join(tmp, name + '.qsp'), opts, live, tmp)
        if data is None:
            continue
        # (3.8, or 3.12 for a polygon mesh with interior vertices: its interior positions section)
        minor = 12 if 0x0c in g.sections(data) else 8
        if not expect(data[9] == minor and 0x0b in g.sections(data), '%s: a %d.%d file without a colours section' % (
                name, data[8], data[9])):
            continue
        flags = g.sections(data)[0x0b][0]
        if flags & 7:
            pg_files[bool(flags & 0x40)].append(name)
        if name in WANT_PG:
            expect(bool(flags & 0x40) == WANT_PG[name], '%s: flag bit 6 (parallelograms) %s, expected %s' % (
                name, 'set' if flags & 0x40 else 'clear', 'set' if WANT_PG[name] else 'clear'))
        mesh = check_file(name, data, src, '--keep-order' in opts, qsp, tmp, live)
        if mesh is not None:
            n += 1 + check_variants(name, data, qsp, tmp, live)
    bound_case(qsp, tmp, live)
    constant_case(qsp, tmp, live)
    for pg in (True, False):
        expect(pg_files[pg], 'no file with vertex colours and flag bit 6 %s' % ('set' if pg else 'clear'))
    NOTES.append('flag bit 6 set in %s; clear in %s' % (', '.join(pg_files[True]), ', '.join(pg_files[False])))
    # every branch of the vertex predictions met
    for rule in ('colors: vertex m=1', 'colors: vertex m=2', 'colors: vertex with more than 8 parallelograms',
                 'colors: parallelograms flag, m=0, vertex n=0, first', 'colors: parallelograms flag, m=0, vertex n=0, previous',
                 'colors: parallelograms flag, m=0, vertex n=1', 'colors: parallelograms flag, m=0, vertex n=2',
                 'colors: vertex n=0, first', 'colors: vertex n=0, previous', 'colors: vertex n=1', 'colors: vertex n=2',
                 'colors: mean clamped', 'colors: encoder: parallelograms smaller', 'colors: encoder: parallelograms larger'):
        expect(c.STATS.get(rule), 'a rule never met: %s' % rule)
    return n


def main():
    args = sys.argv[1:]
    if args[:1] == ['--test'] and len(args) <= 2:
        qsp = args[1] if len(args) == 2 else '/work/main/build/qsp'
        with tempfile.TemporaryDirectory() as tmp:
            n = test(qsp if os.path.exists(qsp) else None, tmp)
        for note in NOTES:
            print('colorsgen: note: ' + note)
        print('colorsgen: rules met: ' + ', '.join('%s %d' % kv for kv in sorted(c.STATS.items())))
        print('colorsgen: %s' % ('%d failed' % len(FAILED) if FAILED else 'all hold (%d files)' % n))
        return 1 if FAILED else 0
    if args[:1] == ['--check'] and len(args) in (3, 4):
        qsp = args[3] if len(args) == 4 else None
        live = bool(qsp) and reads_38(qsp)
        data = open(args[1], 'rb').read()
        name = os.path.splitext(os.path.basename(args[1]))[0]
        with tempfile.TemporaryDirectory() as tmp:
            if check_file(name, data, args[2], 'keep_order' in name, qsp, tmp, live) is not None:
                check_variants(name, data, qsp, tmp, live)
        for note in NOTES:
            print('colorsgen: note: ' + note)
        return 1 if FAILED else 0
    if args[:1] == ['--mesh'] and len(args) == 3:
        case = next(cs for cs in CASES if cs[0] == args[1])
        with tempfile.TemporaryDirectory() as tmp:
            src = make(case, tmp)
            open(args[2], 'wb').write(open(src, 'rb').read())
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == '__main__':
    sys.exit(main())
