#!/usr/bin/env python3
"""propsgen.py: meshes with PLY vertex and face properties and OBJ vertex weights, and properties
sections (qsp_format.md "Properties section", format 3.14) broken each way the text names, to test
qsppoly.py's decoder of that section (qspprops.py) and qsp decompress.

usage: propsgen.py --make DIR
       writes small meshes into DIR and prints a line `NAME<TAB>MESH` for each: a binary PLY quad grid
       with vertex properties of every type (char .. double, each type's extremes, float and double
       NaN, infinities, -0 and subnormals, doubles binary32 does not hold, doubles binary32's shortest
       texts hold, a double equal to a widened binary32 whose text is long) and face lists with each
       count type (char .. uint); an ASCII PLY with a triangle beside quads, a float property with
       values of more digits than binary32, a double one of short texts and lists of floats; and an
       OBJ with vertex weights `v x y z w` (some of more digits than binary32).
       propsgen.py --test FILE.qsp QSP WORKDIR [MESH]
       FILE holds a properties section: decodes it with qsppoly.py; with MESH (the mesh FILE was made
       from), compares the properties with MESH's (names, types, header order, every value exactly,
       flags bit 2 on a float property exactly where some value is not binary32's); runs `QSP
       decompress -f FILE -o WORKDIR/x.ply` (x.obj for a section of a weight alone) and checks that
       every vertex's and face's property values are the Python decoder's (vertices matched by position bits, faces by
       their corners' positions; index for index with an order section), each property's type, list
       count type and header order; that the section is the one qspprops.encode_props writes back
       (every varint minimal, nothing else); and that both decoders read valid rewrites of the section
       (a float property in binary64, NaN and infinities, a name of every printable byte) to the same
       values and refuse the section broken each way the text names (in a 3.13 file, count 0, a count
       past the bytes / 3, reserved flag bits, value types 8 and 15, a scalar with a list length type,
       a float list length type, bit 2 on an integer type, names with bytes outside 0x21-0x7e or past
       the section, empty names other than one scalar float vertex weight, a vertex property after a
       face property, a list length past its type's maximum, list lengths summing to 2^32, integer
       values outside their type's range, a zigzag value of 2^34, a count above 65,536, a non-minimal varint, a byte after
       the last property, a byte short, two properties of one element with one name). Exit 0 if all hold,
       else 1.
"""
import math
import os
import random
import struct
import subprocess
import sys

import qspgeo as g
import qspexact as x
import qsppoly as poly
import qspprops as qp
import qspvalues as qv

TYPES = qp.TYPES
ALIASES = {b'int8': b'char', b'uint8': b'uchar', b'int16': b'short', b'uint16': b'ushort', b'int32': b'int',
           b'uint32': b'uint', b'float32': b'float', b'float64': b'double'}
FMT = {b'char': 'b', b'uchar': 'B', b'short': 'h', b'ushort': 'H', b'int': 'i', b'uint': 'I', b'float': 'f',
       b'double': 'd'}
KNOWN = {b'x', b'y', b'z', b'vertex_indices', b'vertex_index'}
DOUBLE_CLEAR_IS_SHORTEST = True  # "each the exact value of its type (a binary64 for floats) ... text as a
                              # text that reads back to the value (binary32's shortest where bit 2 is
                              # clear)": which binary64 a `double` property's value with bit 2 clear is
                              # (its binary32 widened, or the value of the binary32's shortest text) the
                              # text leaves open; qsp writes the latter to a binary PLY `double` (and
                              # its encoder clears bit 2 only where every value is that, so the source's
                              # binary64 comes back), a `float` property's written as `double` the former
NAN_FLOAT_AS_DOUBLE = False   # qsp once wrote a `float` property (flags bit 2 clear) holding a NaN as a
                              # PLY `double`; the text says "in their types", and it now keeps `float`
WIDE_FLOAT_AS_DOUBLE = True   # "the decoder writes them back in their types (PLY: `property TYPE NAME`
                              # ...), text as a text that reads back to the value": a `float` property
                              # with flags bit 2 (values binary32 does not hold) cannot be written back
                              # as a binary PLY `float`; qsp writes binary PLY only and declares it
                              # `double` there (the text does not say so): accepted, values compared
                              # as binary64


# ---------------- reading what qsp decompress wrote ----------------
def read_ply(path):
    """A PLY file (binary_little_endian or ascii): {element name: (count, [(name, type words)], rows)}
    with each row a dict name -> value: an integer, ('f', bits32) / ('d', bits64) for binary floats,
    ('t', text) for ascii floats, a list of those for a list property."""
    data = open(path, 'rb').read()
    elements, fmt, end = x.ply_header(data)
    g.need(fmt in (b'ascii', b'binary_little_endian'), '%s: PLY format %s' % (path, fmt))
    words = data[end:].split() if fmt == b'ascii' else None
    at, wi = end, 0

    def one(t):
        nonlocal at, wi
        t = ALIASES.get(t, t)
        if words is not None:
            wi += 1
            w = words[wi - 1]
            return ('t', w.decode()) if t in (b'float', b'double') else int(w)
        c = FMT[t]
        if t in (b'float', b'double'):
            c = 'I' if t == b'float' else 'Q'
            v = struct.unpack_from('<' + c, data, at)[0]
            at += struct.calcsize(c)
            return ('f' if t == b'float' else 'd', v)
        v = struct.unpack_from('<' + c, data, at)[0]
        at += struct.calcsize(c)
        return v

    out = {}
    for name, n, props in elements:
        rows = []
        for _ in range(n):
            row = {}
            for pname, ptype in props:
                if ptype[0] == b'list':
                    k = one(ptype[1])
                    row[pname] = [one(ptype[2]) for _ in range(k)]
                else:
                    row[pname] = one(ptype[0])
            rows.append(row)
        out[name] = (n, props, rows)
    g.need(words is None or wi == len(words), '%s: %d words after the last element' % (path, len(words or []) - wi))
    g.need(words is not None or at == len(data), '%s: %d bytes after the last element' % (path, len(data) - at))
    return out


def pos_bits(v):
    """Position bits of a PLY coordinate as read_ply gives it."""
    if isinstance(v, tuple):
        if v[0] == 'f':
            return v[1]
        return g.f32_bits_of_double(qp.as_float(v[1]) if v[0] == 'd' else float(v[1]))
    return g.f32_bits_of_double(float(v))


def same_value(p, mine, theirs):
    """Whether one decoded value (int, or binary64 bits) is what the writer wrote (read_ply's), and why not."""
    if p['type'] not in qp.FLOATS:
        return mine == theirs, ''
    if not isinstance(theirs, tuple):
        return False, 'an integer written for a float'
    kind, v = theirs
    nan = is_nan(mine)
    if kind == 'd':   # NaN included: its bits exactly ("Any bits are a value")
        if DOUBLE_CLEAR_IS_SHORTEST and p['type'] == 7 and not p['wide']:
            return v == shortest_value(qp.narrow(mine)), ''
        return v == mine, ''
    if kind == 'f':
        n = qp.narrow(mine)
        if n is None:
            return False, 'a value binary32 does not hold written as a PLY float'
        return v == n, ''
    # text: it reads back to the value (binary32's where bit 2 is clear)
    try:
        y = float(v)
    except ValueError:
        return False, 'text %r' % v
    if nan:
        return math.isnan(y), ''
    if p['wide']:
        return x.f64_bits(y) == mine, ''
    return g.f32_bits_of_double(y) == qp.narrow(mine), ''


def is_nan(b):
    return b >> 52 & 0x7FF == 0x7FF and b & ((1 << 52) - 1) != 0


def has_nan(p):
    flat = [y for v in p['values'] for y in v] if p['list'] else p['values']
    return any(is_nan(b) for b in flat)


def compare_ply(mesh, path, exact):
    """The decoded properties (mesh: qsppoly.decode_file's) against the PLY qsp decompress wrote."""
    pos, faces, props = mesh[0], mesh[1], mesh[11]
    ply = read_ply(path)
    bad = []
    if b'vertex' not in ply or b'face' not in ply:
        return ['%s has no vertex or face element' % path]
    nv, vprops, vrows = ply[b'vertex']
    nf, fprops, frows = ply[b'face']
    if nv != len(pos) or nf != len(faces):
        return ['%d vertices and %d faces, qsp decompress wrote %d and %d' % (len(pos), len(faces), nv, nf)]
    wpos = [tuple(pos_bits(r[k]) for k in (b'x', b'y', b'z')) for r in vrows]
    fkey = b'vertex_index' if any(n == b'vertex_index' for n, _ in fprops) else b'vertex_indices'
    wfaces = [r[fkey] for r in frows]
    # vertices: by position bits (index for index with an order section)
    if exact:
        vmap = list(range(len(pos)))
        if wpos != pos:
            bad.append('positions differ index for index from what qsp decompress wrote')
    else:
        at = {}
        for j, p in enumerate(wpos):
            at.setdefault(p, []).append(j)
        if any(len(v) > 1 for v in at.values()):
            bad.append('two written vertices at one position: matched index for index')
            vmap = list(range(len(pos)))
        else:
            vmap = [at.get(p, [None])[0] for p in pos]
            if None in vmap:
                return bad + ['vertex %d at %s is not among those qsp decompress wrote' % (vmap.index(None), pos[vmap.index(None)])]
    # faces: by their corners' positions (a rotation of the cycle), index for index with an order section

    def cyc(c):
        c = list(c)
        k = min(range(len(c)), key=lambda i: c[i:] + c[:i])
        return tuple(c[k:] + c[:k])

    if exact:
        fmap = list(range(len(faces)))
        if [cyc(pos[v] for v in f) for f in faces] != [cyc(wpos[v] for v in f) for f in wfaces]:
            bad.append('faces\' corner positions differ index for index from what qsp decompress wrote')
    else:
        at = {}
        for j, f in enumerate(wfaces):
            at.setdefault(cyc(wpos[v] for v in f), []).append(j)
        fmap = []
        for i, f in enumerate(faces):
            lst = at.get(cyc(pos[v] for v in f))
            if not lst:
                return bad + ['face %d is not among those qsp decompress wrote' % i]
            fmap.append(lst.pop(0))
    # properties: names, types, order, values
    for face, hprops, rows, mp in ((False, vprops, vrows, vmap), (True, fprops, frows, fmap)):
        mine = [p for p in props if p['face'] == face and p['name']]
        names = [n for n, _ in hprops if n not in KNOWN]
        written = [n for n, _ in hprops if n in {p['name'] for p in mine}]
        if written != [p['name'] for p in mine]:
            bad.append('%s properties %s, qsp decompress wrote %s (all: %s)' % (
                'face' if face else 'vertex', [p['name'] for p in mine], written, names))
            continue
        htype = {n: [ALIASES.get(w, w) for w in t] for n, t in hprops}
        for p in mine:
            t = htype[p['name']]
            vt = TYPES[p['type']].encode()
            want = [b'list', TYPES[p['count_type']].encode(), vt] if p['list'] else [vt]
            if WIDE_FLOAT_AS_DOUBLE and p['wide'] and vt == b'float' and t[-1:] == [b'double']:
                want = want[:-1] + [b'double']
            if NAN_FLOAT_AS_DOUBLE and vt == b'float' and t[-1:] == [b'double'] and has_nan(p):
                want = want[:-1] + [b'double']
            if t != want:
                bad.append('%r: type %s, qsp decompress wrote %s' % (p['name'], b' '.join(want).decode(), b' '.join(t).decode()))
                continue
            wrong = []
            for i, v in enumerate(p['values']):
                w = rows[mp[i]][p['name']]
                if p['list']:
                    if len(v) != len(w):
                        wrong.append((i, 'a list of %d, written %d' % (len(v), len(w))))
                        continue
                    why = [same_value(p, a, b) for a, b in zip(v, w)]
                    if not all(ok for ok, _ in why):
                        wrong.append((i, '%s, written %s %s' % (v, w, [y for ok, y in why if not ok][:1])))
                else:
                    ok, y = same_value(p, v, w)
                    if not ok:
                        wrong.append((i, '%s, written %s %s' % (hex(v) if p['type'] in qp.FLOATS else v, w, y)))
            if wrong:
                bad.append('%r (%s): %d %ss\' values differ from what qsp decompress wrote (first: %d: %s)' % (
                    p['name'], ' '.join(x.decode() for x in want), len(wrong), 'face' if face else 'vertex',
                    wrong[0][0], wrong[0][1]))
    return bad


def compare_obj_weights(mesh, path, exact):
    """The vertex weight (the empty-named property) against `v x y z w` of the OBJ qsp decompress wrote."""
    pos, props = mesh[0], mesh[11]
    w = [p for p in props if not p['name']]
    if not w:
        return []
    w = w[0]
    vs = []
    for raw in open(path, 'rb').read().split(b'\n'):
        t = raw.split()
        if t[:1] == [b'v']:
            vs.append((tuple(g.f32_bits_of_double(float(a)) for a in t[1:4]), t[4:]))
    if len(vs) != len(pos):
        return ['%d vertices, qsp decompress wrote %d to the OBJ' % (len(pos), len(vs))]
    if exact:
        order = list(range(len(pos)))
    else:
        at = {p: j for j, (p, _) in enumerate(vs)}
        order = [at.get(p) for p in pos]
        if None in order:
            return ['vertex %d is not among those qsp decompress wrote to the OBJ' % order.index(None)]
    bad = []
    for i, v in enumerate(w['values']):
        rest = vs[order[i]][1]
        if len(rest) != 1:
            bad.append('vertex %d: the OBJ has %d numbers after x y z, not the weight alone' % (i, len(rest)))
            break
        ok, why = same_value(w, v, ('t', rest[0].decode()))
        if not ok:
            bad.append('vertex %d: weight %r, qsp decompress wrote %s %s' % (i, qp.as_float(v), rest[0].decode(), why))
            break
    return bad


# ---------------- the mesh the file was made from ----------------
OTHER_PLACES = {b'x', b'y', b'z', b'nx', b'ny', b'nz', b'u', b'v', b's', b't', b'texture_u', b'texture_v', b'red',
                b'green', b'blue', b'alpha', b'vertex_indices', b'vertex_index'}   # the places qsp has for them


def source_value(p, v):
    """A source value (read_ply's, or ('t', text) of an OBJ weight) as the binary64 bits or int the
    decoded property must give, and whether binary32 holds it the way bit 2 clear keeps it (its
    binary32's shortest text's value, or binary32 data)."""
    if p['type'] not in qp.FLOATS:
        return v, True
    kind, u = v
    if kind == 'f':
        return qp.widen(u), True
    y = qp.as_float(u) if kind == 'd' else float(u)
    b = f64(y)
    if y != y or math.isinf(y):
        return b, True
    n = g.f32_bits_of_double(y)
    held = n & 0x7FFFFFFF != 0x7F800000 and shortest_value(n) == b
    return (qp.widen(n) if held and p['type'] == 6 and not p['wide'] else b), held


def shortest_value(n):
    """The binary64 bits of the value binary32 n's shortest text denotes (n itself if not finite)."""
    if n & 0x7F800000 == 0x7F800000:
        return qp.widen(n)
    return f64(qv.text_value(n))


def compare_source(mesh, path, exact):
    """The decoded properties against the mesh FILE was made from (PLY: every vertex and face property
    but those qsp has other places for, in header order; OBJ: the weight of `v x y z w`): names, types,
    list count types, order, and every value exactly (a value of bit 2 clear: its binary32's, or, for a
    `double`, its shortest text's value); bit 2 set on a `float` property exactly where some value is
    not binary32's (the reference encoder's choice the text states)."""
    pos, faces, props = mesh[0], mesh[1], mesh[11]
    if path.endswith('.obj'):
        spos, sfaces, w = [], [], []
        for raw in open(path, 'rb').read().split(b'\n'):
            t = raw.split()
            if t[:1] == [b'v']:
                spos.append(tuple(g.f32_bits_of_double(float(a)) for a in t[1:4]))
                w.append(('t', t[4].decode()) if len(t) == 5 else None)
            elif t[:1] == [b'f']:
                sfaces.append([int(a.split(b'/')[0]) - 1 for a in t[1:]])
        want = [(b'', False, None, None, w)] if any(w) else []
    else:
        ply = read_ply(path)
        _, vprops, vrows = ply[b'vertex']
        _, fprops, frows = ply[b'face']
        spos = [tuple(pos_bits(r[k]) for k in (b'x', b'y', b'z')) for r in vrows]
        fkey = b'vertex_index' if any(n == b'vertex_index' for n, _ in fprops) else b'vertex_indices'
        sfaces = [r[fkey] for r in frows]
        want = [(n, face, [ALIASES.get(a, a) for a in t], None, [r[n] for r in rows])
                for face, hp, rows in ((False, vprops, vrows), (True, fprops, frows)) for n, t in hp
                if n not in OTHER_PLACES]
    bad = []
    if [(p['name'], p['face']) for p in props] != [(n, f) for n, f, _, _, _ in want]:
        return ['properties %s, the mesh has %s' % ([(p['name'], p['face']) for p in props],
                                                    [(n, f) for n, f, _, _, _ in want])]

    def cyc(c):
        c = list(c)
        k = min(range(len(c)), key=lambda i: c[i:] + c[:i])
        return tuple(c[k:] + c[:k])

    if exact:
        vmap, fmap = list(range(len(pos))), list(range(len(faces)))
    else:
        at = {q: j for j, q in enumerate(spos)}
        vmap = [at.get(q) for q in pos]
        fat = {}
        for j, f in enumerate(sfaces):
            fat.setdefault(cyc(spos[v] for v in f), []).append(j)
        fmap = [(fat.get(cyc(pos[v] for v in f)) or [None]).pop(0) for f in faces]
        if None in vmap or None in fmap or len(set(vmap)) != len(vmap):
            return ['vertices or faces not matched to the mesh\'s by their positions']
    for p, (n, face, t, _, vals) in zip(props, want):
        if t is not None:
            mine = [b'list', TYPES[p['count_type']].encode(), TYPES[p['type']].encode()] if p['list'] else [TYPES[p['type']].encode()]
            if mine != t:
                bad.append('%r: type %s, the mesh %s' % (n, b' '.join(mine).decode(), b' '.join(t).decode()))
                continue
        mp = fmap if face else vmap
        held, wrong = True, None
        for i, v in enumerate(p['values']):
            sv = vals[mp[i]]
            pairs = list(zip(v, sv)) if p['list'] else [(v, sv)]
            if p['list'] and len(v) != len(sv):
                wrong = wrong or (i, 'a list of %d, the mesh %d' % (len(v), len(sv)))
                continue
            for a, b in pairs:
                e, h = source_value(p, b)
                held = held and h
                if p['type'] in qp.FLOATS and not p['wide'] and not is_nan(a) and p['type'] == 7:
                    a = shortest_value(qp.narrow(a)) if DOUBLE_CLEAR_IS_SHORTEST else a
                text_nan = p['type'] in qp.FLOATS and b[0] == 't' and is_nan(e)   # a text's NaN: any NaN
                ok = is_nan(a) if text_nan else a == e
                if not ok:
                    wrong = wrong or (i, '%s, the mesh %s' % (hex(a) if p['type'] in qp.FLOATS else a, b))
        if wrong:
            bad.append('%r: values differ from the mesh\'s (first: %s %d: %s)' % (n, 'face' if face else 'vertex', *wrong))
        if p['type'] == 6 and p['wide'] == held:
            bad.append('%r: flags bit 2 %s, and %s value binary32 does not hold' % (
                n, 'set' if p['wide'] else 'clear', 'no' if held else 'some'))
    return bad


# ---------------- variants of a file's section ----------------
def reseal(data, secs, minor=None):
    return g.container(data[:9] + bytes([data[9] if minor is None else minor]) + data[10:11], secs)


def clone(props):
    return [dict(p, values=[list(v) if isinstance(v, list) else v for v in p['values']]) for p in props]


def f64(y):
    return x.f64_bits(y)


def variants(data):
    """(what, file bytes, valid) of FILE's properties section rewritten."""
    secs = g.sections(data)
    sec = bytes(secs[0x0e])
    mesh = poly.decode_file(data)
    V, F = len(mesh[0]), len(mesh[1])
    base = qp.decode_props(sec, V, F, data[9])
    out = [('the file itself', data, True)]

    def put(what, payload, valid=False, minor=None):
        out.append((what, reseal(data, {**secs, 0x0e: payload}, minor), valid))

    def with_props(what, ps, valid=False):
        put(what, qp.encode_props(ps), valid)

    def at_prop(i):
        """The offset of property i's flags byte in the section."""
        return len(g.varint(len(base))) + len(qp.encode_props(base[:i])) - len(g.varint(i))

    # valid rewrites
    floats = [i for i, p in enumerate(base) if p['type'] in qp.FLOATS and not p['wide']]
    if floats:
        ps = clone(base)
        ps[floats[0]]['wide'] = True
        with_props('property %r in binary64 (flags bit 2, the same values)' % ps[floats[0]]['name'], ps, True)
    scal = [i for i, p in enumerate(base) if p['type'] in qp.FLOATS and not p['list'] and len(p['values']) >= 4]
    if scal:
        ps = clone(base)
        p = ps[scal[0]]
        specials = [0x7FF0000000000000, 0xFFF0000000000000, 0x7FF8000000000000, 0x8000000000000000]
        if p['wide']:
            specials.append(0x7FF0000000000123)   # a signalling NaN with a payload binary32 does not hold
        p['values'][:len(specials)] = specials
        with_props('property %r with infinities, NaN and -0' % p['name'], ps, True)
    named = [i for i, p in enumerate(base) if p['name']]
    if named:
        ps = clone(base)
        ps[named[0]]['name'] = bytes(range(0x21, 0x7F))
        with_props('a name of every byte 0x21 to 0x7e', ps, True)
    # refused
    put('the section in a 3.13 file', sec, minor=13)
    put('an empty section', b'')
    put('count 0 (the properties after it)', g.varint(0) + sec[len(g.varint(len(base))):])
    put('count 0 alone', g.varint(0))
    rest = sec[len(g.varint(len(base))):]
    put('count past the bytes left / 3', g.varint(len(rest) // 3 + 1) + rest)
    put('count one more than the properties', g.varint(len(base) + 1) + rest)
    put('count 65,537, above the limit, in bytes enough for it', g.varint(65537) + bytes(3 * 65537))
    if len(base) > 1:
        put('count one less than the properties (bytes after the last)', g.varint(len(base) - 1) + rest)
    first = len(g.varint(len(base)))
    for b in (3, 7):
        s = bytearray(sec)
        s[first] |= 1 << b
        put('reserved flags bit %d' % b, bytes(s))
    for t in (8, 15):
        s = bytearray(sec)
        s[first + 1] = s[first + 1] & 0xF0 | t
        put('value type %d' % t, bytes(s))
    scalars = [i for i, p in enumerate(base) if not p['list']]
    lists = [i for i, p in enumerate(base) if p['list']]
    ints = [i for i, p in enumerate(base) if p['type'] not in qp.FLOATS]
    if scalars:
        i = scalars[0]
        s = bytearray(sec)
        s[at_prop(i) + 1] |= 0x10
        put('scalar property %r with a list length type 1' % base[i]['name'], bytes(s))
    for i in lists[:1]:
        for lt in (6, 7, 8):
            ps = clone(base)
            ps[i]['count_type'] = lt
            with_props('list %r with length type %d' % (base[i]['name'], lt), ps)
    if ints:
        ps = clone(base)
        ps[ints[0]]['wide'] = True
        with_props('flags bit 2 on integer property %r' % base[ints[0]]['name'], ps)
    if named:
        i = named[0]
        for bad_name, why in ((b'a b', 'a space'), (b'a\x7fb', '0x7f'), (b'\xe9t\xe9', 'bytes above 0x7f'),
                              (b'a\nb', 'a line feed')):
            ps = clone(base)
            ps[i]['name'] = bad_name
            with_props('a name with %s' % why, ps)
        put('a name length past the section', sec[:at_prop(i) + 2] + g.varint(len(sec)) + b'x')
    for i, p in enumerate(base):
        if p['name'] and (p['face'] or p['list'] or p['type'] not in qp.FLOATS):
            ps = clone(base)
            ps[i]['name'] = b''
            with_props('an empty name on %s property %r (%s%s)' % ('a face' if p['face'] else 'a vertex', p['name'],
                                                                  'list of ' if p['list'] else '', TYPES[p['type']]), ps)
    weight = {'name': b'', 'face': False, 'list': False, 'type': 6, 'count_type': None, 'wide': False,
              'values': [f64(0.5)] * V}
    # the empty name's rules on sections of weights alone (qsp writes a weight to an OBJ, which holds
    # no PLY property, and refuses to write one to a PLY)
    with_props('a section of one vertex weight (float)', [dict(weight)], True)
    with_props('a section of one vertex weight (double, binary64)',
               [dict(weight, type=7, wide=True, values=[f64(0.1 * k) for k in range(V)])], True)
    with_props('two vertex weights', [dict(weight), dict(weight, values=list(weight['values']))])
    with_props('an empty name on an int vertex property', [dict(weight, type=4, values=[1] * V)])
    with_props('an empty name on a vertex list of floats', [dict(weight, list=True, count_type=1, values=[[f64(1.0)]] * V)])
    with_props('an empty name on a face float property', [dict(weight, face=True, values=[f64(1.0)] * F)])
    with_props('an empty name on a vertex property after a face property',
               [dict(weight, name=b'q', face=True, values=[f64(1.0)] * F), dict(weight)])
    vcount = sum(1 for p in base if not p['face'])
    if named:
        i = named[0]
        ps = clone(base)
        twin = dict(ps[i])
        ps.insert(i + 1, twin)
        with_props('two %s properties named %r' % ('face' if base[i]['face'] else 'vertex', base[i]['name']), ps)
    faces_ = [i for i, p in enumerate(base) if p['face']]
    verts_ = [i for i, p in enumerate(base) if not p['face']]
    if faces_ and verts_:
        ps = clone(base)
        ps = [ps[j] for j in faces_[:1]] + [ps[j] for j in range(len(ps)) if j != faces_[0]]
        with_props('a vertex property after a face property', ps)
    if V and faces_:
        ps = clone(base)
        ps.append(dict(weight, name=b'late', face=False, type=1, values=[0] * V))
        with_props('a vertex property after the last face property', ps)
    for i in lists[:1]:
        for lt, n in ((0, 128), (1, 256)):
            n_elems = F if base[i]['face'] else V
            if not n_elems:
                continue
            ps = clone(base)
            ps[i]['count_type'] = lt
            v0 = 0 if base[i]['type'] not in qp.FLOATS else f64(1.0)
            ps[i]['values'] = [[v0] * min(len(v), 127 if lt == 0 else 255) for v in ps[i]['values']]
            with_props('list %r with length type %s and lengths at its maximum (valid)' % (base[i]['name'], TYPES[lt]),
                       ps, True)
            ps[i]['values'][0] = [v0] * n
            with_props('list %r with a length of %d, past %s\'s maximum' % (base[i]['name'], n, TYPES[lt]), ps)
        # lengths summing to 2^32 (two uint lengths of 2^31), values left out: refused either way
        n_elems = F if base[i]['face'] else V
        if n_elems >= 2:
            p = base[i]
            head = bytes([int(p['face']) | 2, p['type'] | 5 << 4]) + g.varint(len(p['name'])) + p['name']
            body = g.varint(1 << 31) * 2 + g.varint(0) * (n_elems - 2)
            before = qp.encode_props(base[:i])[len(g.varint(i)):] if i else b''
            after = qp.encode_props(base[i + 1:])[len(g.varint(len(base) - i - 1)):] if i + 1 < len(base) else b''
            put('list %r with lengths summing to 2^32' % p['name'], g.varint(len(base)) + before + head + body + after)
    types_done = set()
    for i in ints:   # each integer type the section has, once
        p = base[i]
        if p['type'] in types_done:
            continue
        types_done.add(p['type'])
        lo, hi = qp.RANGE[p['type']]
        for val, what in ((hi + 1, 'above'), (lo - 1, 'below')):
            ps = clone(base)
            vs = ps[i]['values']
            if p['list']:
                k = next((j for j, v in enumerate(vs) if v), None)
                if k is None:
                    continue
                vs[k][0] = val
            else:
                if not vs:
                    continue
                vs[0] = val
            with_props('value %d of %r, %s %s\'s range' % (val, p['name'], what, TYPES[p['type']]), ps)
    for i in ints:
        p = base[i]
        n = sum(len(v) for v in p['values']) if p['list'] else len(p['values'])
        if not n:
            continue
        s = sec
        at = at_prop(i)
        hdr = 2 + len(g.varint(len(p['name']))) + len(p['name'])
        if p['list']:
            k = at + hdr
            for _ in p['values']:
                _, k = g.read_varint(s, k)
        else:
            k = at + hdr
        z, k2 = g.read_varint(s, k)
        put('a zigzag value of 2^34 (%r)' % p['name'], s[:k] + g.varint(1 << 34) + s[k2:])
        put('a non-minimal varint value (%r)' % p['name'], s[:k] + bytes([s[k] | 0x80, 0]) + s[k + 1:] if k2 == k + 1
            else s[:k] + s[k:k2 - 1] + bytes([s[k2 - 1] | 0x80, 0]) + s[k2:])
        break
    put('a byte after the last property', sec + b'\0')
    put('the section a byte short', sec[:-1])
    return out, base


def refusals(path, qsp, tmp):
    data = open(path, 'rb').read()
    failed = []
    cases, base = variants(data)
    m0 = poly.decode_file(data)
    V, F = len(m0[0]), len(m0[1])
    if qp.encode_props(base) != bytes(g.sections(data)[0x0e]):
        failed.append('the section is not what qspprops.encode_props writes back from its decoded properties')
    for i, (what, b, valid) in enumerate(cases):
        try:
            mesh = poly.decode_file(b)
            ok, why = True, ''
        except g.FormatError as e:
            ok, why = False, str(e)
        if ok != valid:
            failed.append('qsppoly.py %s %s%s' % ('refuses' if valid else 'does not refuse', what,
                                                  ': ' + why if why else ''))
        f = '%s/props_case_%d.qsp' % (tmp, i)
        open(f, 'wb').write(b)
        # the output: an OBJ for a section of weights alone (a PLY holds no weight), else a PLY
        try:
            sec = g.sections(b).get(0x0e, b'')
            weights_only = b'\x00' in sec and not any(p['name'] for p in qp.decode_props(sec, V, F, 14))
        except g.FormatError:
            weights_only = False
        suffix = '.obj' if weights_only or (valid and ok and not any(p['name'] for p in mesh[11])) else '.ply'
        r = subprocess.run([qsp, 'decompress', '-f', f, '-o', f + suffix], capture_output=True, text=True)
        err = r.stderr.strip()
        if (r.returncode == 0) != valid:
            failed.append('qsp decompress %s %s%s' % ('refuses' if valid else 'does not refuse', what,
                                                      ': ' + err if err else ''))
        elif not valid and 'cannot hold' in err and 'byte offset' not in err:
            failed.append('qsp decompress refuses %s for its output format, not as a format error: %s' % (what, err))
        elif valid and ok:
            exact = 0x04 in g.sections(b)
            if suffix == '.ply':
                failed += ['qsp decompress of %s: %s' % (what, y) for y in compare_ply(mesh, f + suffix, exact)]
            else:
                failed += ['qsp decompress of %s to an OBJ: %s' % (what, y)
                           for y in compare_obj_weights(mesh, f + suffix, exact)]
    return failed


def test(path, qsp, tmp, source=None):
    os.makedirs(tmp, exist_ok=True)
    data = open(path, 'rb').read()
    secs = g.sections(data)
    if 0x0e not in secs:
        return ['no properties section (0x0e)']
    try:
        mesh = poly.decode_file(data)
    except g.FormatError as e:
        return ['qsppoly.py refuses the file: %s' % e]
    bad = compare_source(mesh, source, 0x04 in secs) if source else []
    return bad + refusals(path, qsp, tmp)   # case 0, the file itself, compares it with qsp decompress's PLY


# ---------------- meshes ----------------
def grid(n, m, tri=False):
    pos = [(i * 1.0, j * 1.0, 0.25 * ((i * 7 + j * 3) % 5)) for j in range(m) for i in range(n)]
    faces = [[j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i] for j in range(m - 1) for i in range(n - 1)]
    if tri:   # one quad split into two triangles
        q = faces.pop(len(faces) // 2)
        faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    return pos, faces


def bits32(u):
    return struct.unpack('<f', struct.pack('<I', u))[0]


def make(d):
    os.makedirs(d, exist_ok=True)
    rng = random.Random(314)
    out = []
    # binary PLY: every type, extremes, special floats; face lists with each count type
    pos, faces = grid(5, 4)
    V, F = len(pos), len(faces)
    vp = [(t, 'p_' + t) for t in TYPES]
    ext = {t: qp.RANGE[k] for k, t in enumerate(TYPES[:6])}
    fspecial = [0x7F800000, 0xFF800000, 0x7FC00000, 0x80000000, 0x00000001, 0x7F7FFFFF, 0x3DCCCCCD]
    dspecial = [0x7FF0000000000000, 0x7FF8000000000000, 0x8000000000000000, 0x0000000000000001,
                f64(0.1), f64(1e300), f64(-2.5)]

    def vval(t, i):
        if t in ext:
            lo, hi = ext[t]
            return [lo, hi, 0, -1 if lo else 1][i] if i < 4 else rng.randint(lo, hi)
        if t == 'float':
            return bits32(fspecial[i]) if i < len(fspecial) else rng.uniform(-10, 10)
        return dspecial[i] if i < len(dspecial) else rng.uniform(-1e6, 1e6)

    counts = ['char', 'uchar', 'short', 'ushort', 'int', 'uint']
    vtypes = ['int', 'float', 'uchar', 'double', 'short', 'uint']
    head = ['ply', 'format binary_little_endian 1.0', 'comment properties of every type',
            'element vertex %d' % V, 'property float x', 'property float y', 'property float z']
    head += ['property %s %s' % (t, n) for t, n in vp]
    head += ['property double d_short', 'property double d_widened']
    head += ['property list uchar int v_ids', 'element face %d' % F, 'property list uchar int vertex_indices']
    head += ['property list %s %s f_list_%s' % (c, vt, c) for c, vt in zip(counts, vtypes)]
    head += ['property float f_quality', 'end_header']
    body = bytearray(('\n'.join(head) + '\n').encode())
    for i, p in enumerate(pos):
        body += struct.pack('<3f', *p)
        for t, _ in vp:
            v = vval(t, i)
            if t == 'float' and i < len(fspecial):
                body += struct.pack('<I', fspecial[i])
            elif t == 'double' and i < len(dspecial):
                body += struct.pack('<Q', dspecial[i])
            else:
                body += struct.pack('<' + FMT[t.encode()], v)
        body += struct.pack('<d', [0.5, 2.0, -0.0, 0.25, 1e10, -3.0][i % 6])   # binary32's shortest texts' values
        body += struct.pack('<Q', [0x3FB99999A0000000, 0x3FE0000000000000][i % 2])   # 0.1's binary32, widened
        k = i % 4
        body += struct.pack('<B', k) + struct.pack('<%di' % k, *[rng.randint(-2 ** 31, 2 ** 31 - 1) for _ in range(k)])
    for j, f in enumerate(faces):
        body += struct.pack('<B4i', 4, *f)
        for c, vt in zip(counts, vtypes):
            k = (j + counts.index(c)) % 4
            body += struct.pack('<' + FMT[c.encode()], k)
            for _ in range(k):
                if vt == 'float':
                    body += struct.pack('<f', rng.uniform(-1, 1))
                elif vt == 'double':
                    body += struct.pack('<d', rng.uniform(-1, 1))
                else:
                    lo, hi = ext[vt]
                    body += struct.pack('<' + FMT[vt.encode()], rng.choice([lo, hi, rng.randint(lo, hi)]))
        body += struct.pack('<f', j * 0.5)
    p = '%s/props_binary.ply' % d
    open(p, 'wb').write(bytes(body))
    out.append(('props_binary', p))
    # ASCII PLY with a triangle beside quads: floats of more digits than binary32, lists of floats
    pos, faces = grid(4, 4, tri=True)
    lines = ['ply', 'format ascii 1.0', 'element vertex %d' % len(pos), 'property float x', 'property float y',
             'property float z', 'property float quality', 'property double confidence', 'property double d_text',
             'property uchar flags',
             'property list ushort float samples', 'element face %d' % len(faces),
             'property list uchar int vertex_indices', 'property int label', 'property list uint double w',
             'end_header']
    texts = ['0.123456789012', '1e-45', '3.4028235e38', '0.1', '-0', '2.5', '0.30000000000000004', '7']
    for i, p_ in enumerate(pos):
        q = texts[i % len(texts)] if i % 3 else '%.9g' % rng.uniform(-5, 5)
        c = rng.choice(['0.1', '%.17g' % rng.random(), '1e300', '-4.000000000000001', '2'])
        s = ' '.join('%.9g' % rng.uniform(-1, 1) if k % 2 else rng.choice(['0.5', '0.123456789']) for k in range(i % 3))
        t = ['0.1', '0.5', '2', '-0', '1e-45', '0.2'][i % 6]   # doubles of binary32's shortest texts
        lines.append('%g %g %g %s %s %s %d %d %s' % (p_ + (q, c, t, i % 256, i % 3, s)))
    for j, f in enumerate(faces):
        lines.append('%d %s %d %d %s' % (len(f), ' '.join(map(str, f)), rng.randint(-2 ** 31, 2 ** 31 - 1), j % 3,
                                         ' '.join('%.17g' % rng.random() for _ in range(j % 3))))
    p = '%s/props_ascii.ply' % d
    open(p, 'w').write('\n'.join(lines) + '\n')
    out.append(('props_ascii', p))
    # OBJ with vertex weights
    pos, faces = grid(4, 3)
    p = '%s/props_weights.obj' % d
    with open(p, 'w') as o:
        for i, q in enumerate(pos):
            w = ['1', '0.5', '0.123456789012345', '2.5e-3', '0.1'][i % 5]
            o.write('v %g %g %g %s\n' % (q + (w,)))
        for f in faces:
            o.write('f %s\n' % ' '.join(str(v + 1) for v in f))
    out.append(('props_weights', p))
    for name, path in out:
        print('%s\t%s' % (name, path))


def main():
    args = sys.argv[1:]
    if args[:1] == ['--make'] and len(args) == 2:
        make(args[1])
        return 0
    if args[:1] == ['--test'] and len(args) in (4, 5):
        failed = test(*args[1:])
        for f in failed:
            print('propsgen: %s: %s' % (args[1], f), file=sys.stderr)
        return 1 if failed else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == '__main__':
    sys.exit(main())
