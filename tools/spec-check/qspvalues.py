#!/usr/bin/env python3
"""The exact values section (0x0d, format 3.13) of a .qsp file, written from format-spec/qsp_format.md
("Exact values section", and the "Exact positions section" whose layout its blocks take) alone, without
reading the codec's C++: the binary64 value of every texture coordinate, normal, vertex colour and face
colour component, from the binary32 values the texture coordinates, normals and colours sections give
(after any order section) and the residuals this section holds.

decode_values() is what qsppoly.py calls; encode_values() writes the section with the choices the text
says the reference encoder makes (a kind only where some value is neither its f nor the value of f's
shortest text, then all its values; modes and widths as for positions), so that a file's section can be
checked byte for byte against it; read_values64(), compare_source() and compare_written() compare the
decoded values with the binary64 values a mesh file's text denotes and with what `qsp decompress` writes.

Points where the text leaves a choice are named by the constants below the imports.
"""
import decimal
import struct

import qspgeo as g
import qspexact as x

need = g.need

KINDS = ('texture coordinates', 'normals', 'vertex colours', 'face colours')   # kinds bits 0 to 3
RESERVED = 0xF0
ARRAY_AFTER_ORDER = True   # "as the decoder returns them (after any order section: the texture
                           # coordinates and normals in their sections' value order, ...)": taken as
                           # the values in the output's numbering (a texture coordinates section's
                           # original numbering applied), as the colours are
GRID_KIND_ACCEPTED = True  # a kind whose section holds its values on a binary grid or octahedral: the
                           # text says the section is present for values "kept exactly (not on a binary
                           # grid, not octahedral)" but names no refusal; a decoder reads it by the
                           # block rules (each value must round to its f)
LAST = {}                  # the last decode_values() call's arrays (binary32 bits) and values


def arrays_of(tex, nrm, colors):
    """The four kinds' arrays as qsppoly.decode_file has them after the order section: per kind None
    (absent) or (binary32 bits per value, K)."""
    out = [None] * 4
    if tex is not None:
        out[0] = (tex[0], len(tex[2]))
    if nrm is not None:
        out[1] = (nrm[0], 3)
    if colors is not None:   # K: the colours section's Kv and Kf
        if colors['vertex'] is not None:
            out[2] = (colors['vertex'], colors['K'][0])
        if colors['face'] is not None:
            out[3] = (colors['face'], colors['K'][1])
    return out


def decode_values(payload, arrays, minor):
    """The section's binary64 values: per kind None or a list of K-tuples, one per value of its
    array. arrays: arrays_of()'s. Raises FormatError on anything the text refuses."""
    need(minor >= 13, 'section 0x0d (exact values) is format 3.13\'s, and the file says it is 3.%d' % minor)
    need(len(payload) >= 1, 'exact values: no kinds byte')
    kinds = payload[0]
    need(kinds & RESERVED == 0, 'exact values: kinds 0x%02x has a reserved bit (4 to 7) set' % kinds)
    need(kinds != 0, 'exact values: kinds 0, no kind')
    at = 1
    out = [None] * 4
    for b in range(4):
        if not kinds >> b & 1:
            continue
        need(arrays[b] is not None, 'exact values: kind %d (%s), which the mesh does not have' % (b, KINDS[b]))
        L, at = g.read_varint(payload, at)
        need(L <= len(payload) - at, 'exact values: %s block of %d bytes, %d left' % (KINDS[b], L, len(payload) - at))
        vals, K = arrays[b]
        fs = [tuple(g.bits_f32(u) for u in v) for v in vals]
        out[b] = x.decode_block(payload[at:at + L], fs, K, 'exact values (%s)' % KINDS[b])
        at += L
    need(at == len(payload), 'exact values: %d bytes after the last block' % (len(payload) - at))
    LAST.update(arrays=arrays, values=out)
    return out


# ---------------- values as a decoder returns them ----------------
def shortest32(u):
    """The shortest text that reads back to binary32 u (the nearest to it among those), as a Decimal."""
    f = g.bits_f32(u)
    if f == 0:
        return decimal.Decimal('-0' if u >> 31 else '0')
    for p in range(1, 10):
        d = decimal.Decimal('%.*e' % (p - 1, f))
        step = decimal.Decimal((0, (1,), d.as_tuple().exponent))
        good = [c for c in (d, d - step, d + step) if g.f32_bits_of_double(float(c)) == u]
        if good:
            return min(good, key=lambda c: abs(c - decimal.Decimal(f)))
    raise AssertionError(u)


def text_value(u):
    """The binary64 a decoder without this section gives for binary32 u when it writes text: the value
    of u's shortest text."""
    return float(shortest32(u))


def values64(arrays, values):
    """Per kind None or a list of K-tuples of binary64: the section's values for its kinds, each other
    array's values as text_value() gives them."""
    out = [None] * 4
    for b in range(4):
        if arrays[b] is None:
            continue
        if values is not None and values[b] is not None:
            out[b] = values[b]
        else:
            out[b] = [tuple(text_value(u) for u in v) for v in arrays[b][0]]
    return out


# ---------------- the reference encoder ----------------
def needs_kind(vals, xs):
    """Whether some value is neither its f nor the value of f's shortest text."""
    for v, p in zip(vals, xs):
        for u, y in zip(v, p):
            if x.f64_bits(y) != x.f64_bits(g.bits_f32(u)) and x.f64_bits(y) != x.f64_bits(text_value(u)):
                return True
    return False


def encode_values(arrays, values):
    """The section (None for none) the text's encoder writes for binary64 values per kind over the
    binary32 arrays."""
    kinds, body = 0, b''
    for b in range(4):
        if arrays[b] is None or values[b] is None or not needs_kind(arrays[b][0], values[b]):
            continue
        kinds |= 1 << b
        fs = [tuple(g.bits_f32(u) for u in v) for v in arrays[b][0]]
        block = x.encode_exact(values[b], fs, K=arrays[b][1])
        body += g.varint(len(block)) + block
    return bytes([kinds]) + body if kinds else None


# ---------------- the meshes' own values ----------------
def read_values64(path):
    """(positions as binary32 bits, faces, per kind None or values as binary64 tuples, per face the
    texture coordinate and normal each corner names) of an .obj, .off or .ply, the values as the
    binary64s their texts denote (a PLY's binary32 and binary64 data as they are)."""
    data = open(path, 'rb').read()
    if data.startswith(b'ply'):
        return read_ply(data)
    lines = [ln.split(b'#')[0].split() for ln in data.split(b'\n')]
    lines = [w for w in lines if w]
    if lines and lines[0][0].endswith(b'OFF'):
        head = lines[0][0]
        rest = lines[0][1:] or lines[1]
        body = lines[1:] if lines[0][1:] else lines[2:]
        nv, nf = int(rest[0]), int(rest[1])
        pos, vc, faces, fc = [], [], [], []
        for w in body[:nv]:
            pos.append(tuple(g.f32_bits_of_double(float(t)) for t in w[:3]))
            vc.append(tuple(float(t) for t in w[3:]))
        for w in body[nv:nv + nf]:
            d = int(w[0])
            faces.append([int(t) for t in w[1:1 + d]])
            fc.append(tuple(float(t) for t in w[1 + d:]))
        vc = vc if b'C' in head and any(vc) else None
        fc = fc if any(fc) else None
        return pos, faces, [None, None, vc, fc], None
    pos, vc, vts, vns, faces, names = [], [], [], [], [], []
    for w in lines:
        if w[0] == b'v':
            pos.append(tuple(g.f32_bits_of_double(float(t)) for t in w[1:4]))
            vc.append(tuple(float(t) for t in w[4:]))
        elif w[0] == b'vt':
            vts.append(tuple(float(t) for t in w[1:]))
        elif w[0] == b'vn':
            vns.append(tuple(float(t) for t in w[1:4]))
        elif w[0] == b'f':
            f, nm = [], []
            for t in w[1:]:
                parts = t.split(b'/')
                i = int(parts[0])
                f.append(i - 1 if i > 0 else len(pos) + i)
                c = []
                for k, arr in ((1, vts), (2, vns)):
                    if len(parts) > k and parts[k]:
                        j = int(parts[k])
                        c.append(j - 1 if j > 0 else len(arr) + j)
                    else:
                        c.append(None)
                nm.append(tuple(c))
            faces.append(f)
            names.append(nm)
    return pos, faces, [vts or None, vns or None, vc if any(vc) else None, None], names


PLY_TYPES = x.PLY_TYPES
NOT_COLOUR = {b'x', b'y', b'z', b'nx', b'ny', b'nz', b'u', b'v', b's', b't', b'texture_u', b'texture_v'}


def read_ply(data):
    elements, fmt, end = x.ply_header(data)
    need(fmt in (b'ascii', b'binary_little_endian'), 'PLY format %s' % fmt)
    words = data[end:].split() if fmt == b'ascii' else None
    at, wi = end, 0

    def one(t):
        nonlocal at, wi
        if words is not None:
            wi += 1
            return float(words[wi - 1])
        ch = PLY_TYPES[t]
        v = struct.unpack_from('<' + ch, data, at)[0]
        at += struct.calcsize(ch)
        return v

    pos, faces, vc, fc, vn = [], [], [], [], []
    for name, n, props in elements:
        for _ in range(n):
            row, col = {}, []
            for pname, ptype in props:
                if ptype[0] == b'list':
                    k = int(one(ptype[1]))
                    row[pname] = [int(one(ptype[2])) for _ in range(k)]
                else:
                    row[pname] = float(one(ptype[0]))
                    if name != b'vertex' or pname not in NOT_COLOUR:
                        col.append(row[pname])
            if name == b'vertex':
                pos.append(tuple(g.f32_bits_of_double(row[k]) for k in (b'x', b'y', b'z')))
                vc.append(tuple(col))
                if b'nx' in row:
                    vn.append((row[b'nx'], row[b'ny'], row[b'nz']))
            elif name == b'face':
                faces.append(row.get(b'vertex_indices', row.get(b'vertex_index')))
                fc.append(tuple(col))
    return pos, faces, [None, vn or None, vc if any(vc) else None, fc if any(fc) else None], None


# ---------------- comparisons ----------------
def key(p):
    return tuple(x.f64_bits(y) for y in p)


def first_diff(a, b):
    return next((i for i in range(min(len(a), len(b))) if a[i] != b[i]), min(len(a), len(b)))


def compare_source(mesh, src, exact):
    """The decoded values (mesh: qsppoly.decode_file's) against src = read_values64() of the mesh the
    file was made from, binary64 bits (-0 and +0 apart): index for index when exact (an order section),
    else each array as a multiset, the texture coordinates and normals also corner by corner (each
    face's corner positions and values, up to rotation and face order), vertex colours with their
    vertices' positions, face colours with their faces' corner positions."""
    pos, faces = mesh[0], mesh[1]
    arrays = arrays_of(mesh[4], mesh[7], mesh[9])
    mine = values64(arrays, mesh[10])
    spos, sfaces, theirs, snames = src
    bad = []
    for b in range(4):
        a, t = mine[b], theirs[b]
        if a is None and t is None:
            continue
        if a is None or t is None:
            bad.append('%s: %s, the mesh %s' % (KINDS[b], 'none' if a is None else len(a), 'none' if t is None else len(t)))
            continue
        K = arrays[b][1]
        t = [tuple(v[:K]) + (0.0,) * (K - len(v)) for v in t]
        ka, kt = [key(v) for v in a], [key(v) for v in t]
        if exact:
            if ka != kt:
                i = first_diff(ka, kt)
                bad.append('%s differ from the mesh\'s, index for index (%d and %d; first at %d: %r, the mesh %r)' % (
                    KINDS[b], len(a), len(t), i, a[i] if i < len(a) else '-', t[i] if i < len(t) else '-'))
            continue
        if sorted(ka) != sorted(kt):
            sa, st = sorted(ka), sorted(kt)
            i = first_diff(sa, st)
            bad.append('%s differ from the mesh\'s as multisets (%d and %d; first: %r, the mesh %r)' % (
                KINDS[b], len(a), len(t), tuple(map(x.f64_of_bits, sa[i])) if i < len(sa) else '-',
                tuple(map(x.f64_of_bits, st[i])) if i < len(st) else '-'))
            continue
        if b in (0, 1) and snames is not None:
            names = (mesh[4] if b == 0 else mesh[7])[1]
            cyc = sorted(_cycle([(pos[v], None if n is None else ka[n]) for v, n in zip(f, nm)])
                         for f, nm in zip(faces, names))
            scyc = sorted(_cycle([(spos[v], None if n[b] is None else kt[n[b]]) for v, n in zip(f, nm)])
                          for f, nm in zip(sfaces, snames))
            if cyc != scyc:
                bad.append('%s: corners\' positions and values differ from the mesh\'s' % KINDS[b])
        elif b == 2:
            if sorted(zip(pos, ka)) != sorted(zip(spos, kt)):
                bad.append('vertex colours differ from the mesh\'s with their vertices\' positions')
        elif b == 3:
            if sorted((_cycle([pos[v] for v in f]), c) for f, c in zip(faces, ka)) != \
                    sorted((_cycle([spos[v] for v in f]), c) for f, c in zip(sfaces, kt)):
                bad.append('face colours differ from the mesh\'s with their faces\' corner positions')
    return bad


def _cycle(c):
    k = min(range(len(c)), key=lambda i: c[i:] + c[:i])
    return tuple(c[k:] + c[:k])


def digits(text):
    t = text.lower().lstrip('+-')
    return t.split('e')[0].replace('.', '').strip('0')


def read_texts(path):
    """Per kind None or the value texts of what a decoder wrote (OBJ: vt, vn, v's colours; OFF: the
    colours after the coordinates and after a face's indices)."""
    lines = [ln.split(b'#')[0].split() for ln in open(path, 'rb').read().split(b'\n')]
    lines = [[t.decode() for t in w] for w in lines if w]
    if lines and lines[0][0].endswith('OFF'):
        rest = lines[0][1:] or lines[1]
        body = lines[1:] if lines[0][1:] else lines[2:]
        nv, nf = int(rest[0]), int(rest[1])
        vc = [tuple(w[3:]) for w in body[:nv]]
        fc = [tuple(w[1 + int(w[0]):]) for w in body[nv:nv + nf]]
        return [None, None, vc if any(vc) else None, fc if any(fc) else None]
    out = [[], [], [], None]
    for w in lines:
        if w[0] == 'vt':
            out[0].append(tuple(w[1:]))
        elif w[0] == 'vn':
            out[1].append(tuple(w[1:]))
        elif w[0] == 'v':
            out[2].append(tuple(w[4:]))
    return [out[0] or None, out[1] or None, out[2] if any(out[2]) else None, None]


def compare_written(mesh, path):
    """The decoded values against the texts `qsp decompress` wrote (read_texts(path)), index for index:
    each text read as binary64 is the value, and no longer, in significant digits, than the shortest
    text that reads back to it."""
    arrays = arrays_of(mesh[4], mesh[7], mesh[9])
    mine = values64(arrays, mesh[10])
    theirs = read_texts(path)
    bad = []
    for b in range(4):
        a, t = mine[b], theirs[b]
        if a is None and t is None:
            continue
        if a is None or t is None:
            bad.append('%s: %s, qsp decompress wrote %s' % (KINDS[b], 'none' if a is None else len(a),
                                                             'none' if t is None else len(t)))
            continue
        ka = [key(v) for v in a]
        kt = [key(tuple(float(s) for s in v)) for v in t]
        if ka != kt:
            i = first_diff(ka, kt)
            bad.append('%s differ from what qsp decompress wrote (%d and %d; first at %d: %r, written %r)' % (
                KINDS[b], len(a), len(t), i, a[i] if i < len(a) else '-', t[i] if i < len(t) else '-'))
            continue
        long = [(i, j, s) for i, v in enumerate(t) for j, s in enumerate(v)
                if len(digits(s)) > len(digits(repr(a[i][j])))]
        if long:
            i, j, s = long[0]
            bad.append('%d %s components written with more digits than the shortest text (first: %d.%d, %s for %r)'
                       % (len(long), KINDS[b], i, j, s, a[i][j]))
    return bad


def compare_encoder(mesh, secs):
    """The file's section against the one the text's encoder writes for the values decoded from it
    (mesh: qsppoly.decode_file's; the kinds without a block are not written). A file without the
    section: nothing to compare (compare_source finds values it lost)."""
    if 0x0d not in secs:
        return []
    arrays = arrays_of(mesh[4], mesh[7], mesh[9])
    mine = encode_values(arrays, mesh[10])
    theirs = bytes(secs[0x0d])
    if mine != theirs:
        return ['the exact values section is not the one the text\'s encoder choices give (kinds 0x%02x, the '
                'text\'s %s; %d and %s bytes)' % (theirs[0], 'none' if mine is None else '0x%02x' % mine[0],
                                                  len(theirs), 'no' if mine is None else len(mine))]
    return []
