#!/usr/bin/env python3
"""exactgen.py: exact positions sections (qsp_format.md "Exact positions section", format 3.6) written
from the text, to test qsppoly.py's decoder of that section (qspexact.py) on payloads no qsp encoder
writes, and meshes whose coordinates binary32 does not hold.

usage: exactgen.py FILE.qsp OUTDIR
       FILE holds an exact positions section; writes into OUTDIR variants of it that break one rule of
       the text each, resealed (size field, checksum), and prints a line `PATH<TAB>WHAT` per variant
       (and `-<TAB>WHAT: skipped, WHY` for one FILE gives no way to build): a mode out of range (23,
       63, 65, 255), a width above 64 (the residuals packed in it), the payload a byte short and a byte
       long, a padding bit set, a residual whose value does not round to f, |N| = 2^63, |p| at or
       above 2^62 (with N below 2^63), binary64 residuals giving +-infinity and a NaN, ord(f) + r past
       the last binary64, a value -0.0 over f = +0.0, the section in a 3.5 and a 3.0 file, and one in
       a quantized golden file (tilted_noise_q14). Every one must be refused by every decoder.
       exactgen.py --digits IN.obj OUT.obj|OUT.off|OUT.ply SEED
       IN's mesh with each `v` line's coordinates replaced by ones binary32 does not hold: ten
       significant digits (x), seventeen (y: arbitrary binary64 values), short decimals such as 0.1
       among binary32 ones and -0 (z), each within half a binary32 step of IN's value; an .obj keeps
       IN's other lines, an .off only vertices and faces, a .ply (binary, x y z as binary64) too.
       exactgen.py --tricky OUT.obj
       a 3x2 grid whose texts need care: a decimal whose binary32 through its binary64 is not its
       binary32 read directly, zeros beyond binary64's digits, 2^62 written out, a value above
       FLT_MAX that rounds to it, -0.
       exactgen.py --put FILE.qsp MESH OUT.qsp
       FILE (MESH compressed with --float32) with the section the text's encoder writes for MESH's
       binary64 values, at minor version 6: a 3.6 file of MESH short of a 3.6 encoder's own choices.
       exactgen.py --test [QSP]
       puts sections into golden files (a quad, an order section, a polygons section, normals beside
       an order section with a -0, a comments section, float-bits axes): valid ones, with the text's
       encoder choices and with given modes (values a binary32 step apart, 2^-150 over +0, N = 0 over
       -0, decimal with 22 decimals, widths 0 and 64), which qsppoly.py must decode to the values they
       were made from, and each one's variants above, which it must refuse. With QSP, also into grids
       `QSP compress --float32` writes of binary32 positions no golden file has (decimal values where
       rounding N to binary64 first goes wrong, ties to even, p just below 2^62, the binary32 overflow
       boundary, subnormals); and, once QSP says it reads 3.6 (`QSP --version`), checks that `QSP
       decompress` refuses each broken file and writes, for each valid one, the values as the shortest
       texts that read back to them. Exit 0 if all hold, else 1.
"""
import math
import os
import random
import struct
import subprocess
import sys
import tempfile

import qspexact as x
import qspgeo as g
import qsppoly as poly

FAILED = []


def expect(ok, what):
    if not ok:
        FAILED.append(what)
        print('exactgen: ' + what, file=sys.stderr)


def ulp32(f):
    """The binary32 step above |f| (f a binary32 as a Python float)."""
    u = g.f32_bits_of_double(abs(f))
    return g.bits_f32(u + 1) - g.bits_f32(u)


# ---------------- files ----------------
def reseal(data, secs, minor=None):
    """data with its sections replaced by secs (size field and checksum recomputed, "File structure")
    and its minor version set."""
    minor = data[9] if minor is None else minor
    return g.container(data[:9] + bytes([minor]) + data[10:11], secs)


def binary32_positions(data):
    """The output vertices' binary32 positions (Python floats) before an order section."""
    pos = poly.canonical_mesh(data, g.sections(data))[0]
    return [tuple(g.bits_f32(u) for u in p) for p in pos]


def with_section(data, payload, minor=None):
    """data with `payload` as its exact positions section, at minor version `minor` (default: 6, or the
    file's own if later: a golden of 3.10's normals stays a 3.10 file)."""
    secs = g.sections(data)
    secs[0x0a] = payload
    return reseal(data, secs, max(6, data[9]) if minor is None else minor)


def unpack(payload, V):
    """modes, widths and residuals[a][v] of a section (no checks)."""
    modes, widths = list(payload[:3]), list(payload[3:6])
    bits = int.from_bytes(payload[6:], 'little')
    res, at = [], 0
    for a in range(3):
        rs = []
        for _ in range(V):
            rs.append(x.unzigzag((bits >> at) & ((1 << widths[a]) - 1)))
            at += widths[a]
        res.append(rs)
    return modes, widths, res


def fit(widths, residuals):
    """Widths at least the given, holding every residual."""
    return [max(w, x.width(rs)) for w, rs in zip(widths, residuals)]


# ---------------- the broken variants ----------------
def variants(data):
    """(what, file bytes or None, why skipped) for each rule the text names, broken in data's section."""
    secs = g.sections(data)
    payload = bytes(secs[0x0a])
    fs = binary32_positions(data)
    V = len(fs)
    modes, widths, res = unpack(payload, V)
    out = []

    def add(what, p, minor=None):
        out.append((what, with_section(data, p, data[9] if minor is None else minor), None))

    def skip(what, why):
        out.append((what, None, why))

    for m in (23, 63, 65, 255):
        add('axis x mode %d' % m, bytes([m]) + payload[1:])
    add('axis y width 65 (its residuals packed in 65 bits)',
        x.pack(modes, res, [widths[0], 65, widths[2]]))
    add('payload one byte short', payload[:-1])
    add('payload one byte long (a zero byte)', payload + b'\x00')
    nbits = V * sum(widths)
    if nbits % 8:
        add('a padding bit set', payload[:-1] + bytes([payload[-1] | 0x80]))
    else:
        skip('a padding bit set', 'the residuals fill whole bytes')

    def values(ms, rs):   # the values, or None if a coordinate is refused
        vals = []
        for a in range(3):
            for v in range(V):
                val, why = x.value_of(fs[v][a], ms[a], rs[a][v])
                if why:
                    return None
                vals.append(val)
        return vals

    ok = values(modes, res) is not None

    def broken(ms, rs):   # one coordinate changed: repacked in widths that hold it
        return x.pack(ms, rs, fit(widths, rs))

    # a residual whose value does not round to f
    done = False
    for a in range(3):
        for v in range(V):
            for d in [s * (1 << e) for e in range(0, 63) for s in (1, -1)]:
                r = res[a][v] + d
                val, why = x.value_of(fs[v][a], modes[a], r)
                if why and why.startswith('value ') and x.zigzag(r) < 1 << 64:
                    rs = [list(t) for t in res]
                    rs[a][v] = r
                    add('axis %d vertex %d: a residual (%d) whose value does not round to f' % (a, v, r),
                        broken(modes, rs))
                    done = True
                    break
            if done:
                break
        if done:
            break
    if not done:
        skip('a residual whose value does not round to f', 'no residual found')

    # decimal axes: N overflow, |p| >= 2^62; an axis made decimal (its values kept) when none is
    dec = [a for a in range(3) if modes[a] != x.BINARY64]
    ms, rs = list(modes), [list(t) for t in res]
    if not dec:
        vals = [[p[a] for p in (values_of_file(data) or [])] for a in range(3)]
        for a in range(3):
            k = max((x.shortest_decimals(t) for t in vals[a]), default=0)
            r_a = [x.residual(t, f[a], k) for t, f in zip(vals[a], fs)] if k <= 22 and vals[a] else [None]
            if None not in r_a:
                ms[a], rs[a] = k, r_a
                dec = [a]
                break
    if dec and ok:
        a = dec[0]
        f = fs[0][a]
        M = x.round_half_away(f * float(10 ** ms[a]))
        r = (1 << 63) - M if M > 0 else -(1 << 63) - M
        rs2 = [list(t) for t in rs]
        rs2[a][0] = r
        add('axis %d vertex 0: N = %s2^63' % (a, '' if M > 0 else '-'), broken(ms, rs2))
    else:
        skip('|N| = 2^63', 'no axis can be decimal' if ok else 'the file\'s own section does not decode')
    done = False
    for a in range(3):   # |p| in [2^62, 2^63) for some coordinate, every other one of the axis valid with r = 0
        for k in range(23):
            ps = [f[a] * float(10 ** k) for f in fs]
            hi = [v for v in range(V) if abs(ps[v]) >= x.P_LIMIT]
            if not hi or any(abs(ps[v]) >= x.N_LIMIT for v in hi):
                continue
            if any(x.value_of(fs[v][a], k, 0)[1] for v in range(V) if v not in hi):
                continue
            ms2, rs2 = list(modes), [list(t) for t in res]
            ms2[a], rs2[a] = k, [0] * V
            add('axis %d in decimal with %d decimals: |p| of vertex %d is %r, at least 2^62 (N below 2^63)' % (
                a, k, hi[0], abs(ps[hi[0]])), broken(ms2, rs2))
            done = True
            break
        if done:
            break
    if not done:
        skip('|p| at least 2^62', 'no axis and decimals give it with N below 2^63')

    # binary64: infinities, a NaN, ord past the last binary64, -0 over +0; an axis made binary64
    vals = values_of_file(data)
    if vals is None:
        skip('binary64 residuals', 'the file\'s own section does not decode')
    else:
        b64 = [a for a in range(3) if modes[a] == x.BINARY64]
        a = b64[0] if b64 else 2
        ms = list(modes)
        rs = [list(t) for t in res]
        ms[a] = x.BINARY64
        rs[a] = [x.ord64(p[a]) - x.ord64(f[a]) for p, f in zip(vals, fs)]
        for what, target in (('+infinity', x.ord64(math.inf)), ('-infinity', x.ord64(-math.inf)),
                             ('a NaN', x.ord64(math.nan))):
            # the nearest vertex on the ord line, so that the residual fits 64 bits
            v = min(range(V), key=lambda v: abs(target - x.ord64(fs[v][a])))
            r = target - x.ord64(fs[v][a])
            if x.zigzag(r) >> 64:
                skip('axis %d: a residual giving %s' % (a, what), 'its residual needs more than 64 bits')
                continue
            rs2 = [list(t) for t in rs]
            rs2[a][v] = r
            add('axis %d (binary64) vertex %d: a residual giving %s' % (a, v, what), broken(ms, rs2))
        v = next((v for v in range(V) if x.f64_bits(fs[v][a]) != 0), None)
        if v is not None:
            o = x.ord64(fs[v][a])
            r = (1 << 63) - o if o >= 0 else -(1 << 63) - o - 1
            rs2 = [list(t) for t in rs]
            rs2[a][v] = r
            add('axis %d (binary64) vertex %d: ord(f) + r = %d, past the %s binary64' % (
                a, v, o + r, 'last' if o >= 0 else 'first'), broken(ms, rs2))
        else:
            skip('ord(f) + r past the last binary64', 'every f of the axis is +0')
        zero = [v for v in range(V) if x.f64_bits(fs[v][a]) == 0]
        if zero:
            rs2 = [list(t) for t in rs]
            rs2[a][zero[0]] = -1
            add('axis %d (binary64) vertex %d: the value -0.0 over f = +0.0' % (a, zero[0]), broken(ms, rs2))
        else:
            skip('-0.0 over +0.0', 'no coordinate of the axis is +0.0')
    add('the section in a 3.5 file', payload, minor=5)
    add('the section in a 3.0 file', payload, minor=0)
    out.append(('a section (binary64, residuals 0) in a quantized file, testdata/golden/tilted_noise_q14.qsp',
                quantized(), None))
    return out


def quantized():
    """A quantized golden file with a section that would be valid in a lossless one (binary64, every
    value its f) at minor version 6."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
    q = open(os.path.join(root, 'testdata/golden/tilted_noise_q14.qsp'), 'rb').read()
    fs = binary32_positions(q)
    return with_section(q, x.encode_exact(fs, fs, [64] * 3))


def values_of_file(data):
    try:
        fs = binary32_positions(data)
        return x.decode_exact(g.sections(data)[0x0a], len(fs), fs, False, 6)
    except g.FormatError:
        return None


# ---------------- meshes whose coordinates binary32 does not hold ----------------
def near(f, rng, digits):
    """A value of `digits` significant digits within half a binary32 step of binary32 f (f itself if
    none is found)."""
    if f == 0:
        return f
    h = ulp32(f) / 2
    for _ in range(50):
        t = float('%.*g' % (digits, f + rng.uniform(-0.9, 0.9) * h))
        if x.f32_bits(t) == x.f32_bits(f):
            return t
    return f


def digits_mesh(src, out, seed):
    """src with every `v` line's coordinates replaced (exactgen.py --digits); an .obj keeps src's other
    lines, an .off only vertices and faces."""
    rng = random.Random(seed)
    lines, vs, fs = open(src, 'rb').read().decode().split('\n'), [], []
    for line in lines:
        w = line.split()
        if w and w[0] == 'v':
            vs.append([g.bits_f32(x.f32_bits(float(t))) for t in w[1:4]])
        elif w and w[0] == 'f':
            fs.append([int(t.split('/')[0]) for t in w[1:]])
    texts = []
    for i, (a, b, c) in enumerate(vs):
        tx = repr(near(a, rng, 10))
        ty = repr(near(b, rng, 17))
        z = [c, 0.1, -0.0, 0.5, 0.3, c][i % 6]   # binary32 ones, short decimals, a -0
        tz = repr(z) if z != c else repr(near(c, rng, 6))
        texts.append('%s %s %s' % (tx, ty, tz))
    if out.endswith('.ply'):   # binary64 PLY data
        head = ('ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty double x\nproperty double y\n'
                'property double z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n' % (
                    len(vs), len(fs)))
        body = b''.join(struct.pack('<3d', *map(float, t.split())) for t in texts)
        body += b''.join(struct.pack('<B%di' % len(f), len(f), *[i - 1 if i > 0 else len(vs) + i for i in f])
                         for f in fs)
        open(out, 'wb').write(head.encode() + body)
        return
    with open(out, 'w') as o:
        if out.endswith('.off'):
            o.write('OFF\n%d %d 0\n' % (len(vs), len(fs)))
            for t in texts:
                o.write(t + '\n')
            for f in fs:
                o.write('%d %s\n' % (len(f), ' '.join(str(i - 1 if i > 0 else len(vs) + i) for i in f)))
            return
        it = iter(texts)
        o.write('\n'.join('v ' + next(it) if line.split()[:1] == ['v'] else line for line in lines))


TRICKY = '''# texts whose binary64 value and binary32 f need care
v 1.0000000596046448 0 -0
v 2 0.5000000000000000000 0.1
v 4611686018427387904 0.1 3.4028235e38
v 0 1 0.30000000000000004
v 1.0000000001 1 -0.0000000001
v 2 1 12345678.9
f 1 2 5 4
f 2 3 6 5
'''


def tricky(out):
    """A 3x2 grid whose texts need care (exactgen.py --tricky): 1.0000000596046448, whose binary64 is
    1 + 2^-24 exactly, halfway between binary32 1 and 1 + 2^-23, so its f (the binary32 nearest the
    value, ties to even) is 1.0 where reading the text to binary32 directly gives 1 + 2^-23; trailing
    zeros beyond binary64's digits; 2^62 written out (a binary32 of a long text); 3.4028235e38, above
    FLT_MAX and rounding to it; 0.30000000000000004; -0."""
    open(out, 'w').write(TRICKY)


def put(data, mesh):
    """data (a .qsp of mesh's positions rounded to binary32, qsp compress --float32) with the section
    the text's encoder writes for mesh's binary64 values (matched to the output vertices by their
    binary32 positions), as a 3.6 file: what a 3.6 encoder writes for mesh, short of its choices of
    partition and coding, for decoders to check before it exists."""
    fs = binary32_positions(data)
    by_f = {}
    for v in x.read_mesh64(mesh)[0]:
        by_f.setdefault(tuple(x.f32_bits(t) for t in v), set()).add(tuple(x.f64_bits(t) for t in v))
    vals = []
    for f in fs:
        got = by_f.get(tuple(x.f32_bits(t) for t in f), set())
        if len(got) != 1:
            raise SystemExit('exactgen: %d values of %s round to the binary32 position %r' % (len(got), mesh, f))
        vals.append(tuple(x.f64_of_bits(u) for u in next(iter(got))))
    return with_section(data, x.encode_exact(vals, fs))


# ---------------- --test ----------------
def nearby(fs, seed):
    """Per vertex values within half a binary32 step of its binary32 f: ten digits on x, arbitrary
    binary64 on y, short decimals or f itself on z."""
    rng = random.Random(seed)
    out = []
    for i, (a, b, c) in enumerate(fs):
        y = b + rng.uniform(-0.49, 0.49) * ulp32(b) if b else 0.0
        out.append((near(a, rng, 10), y if x.f32_bits(y) == x.f32_bits(b) else b, near(c, rng, 2 + i % 3)))
    return out


def handmade(root):
    """(name, file bytes, values per output vertex before an order section, binary32 positions)"""
    out = []

    def golden(name):
        return open(os.path.join(root, 'testdata/golden', name + '.qsp'), 'rb').read()

    quad = golden('quad')
    fs = binary32_positions(quad)   # (0,0,0) (1,0,0) (1,1,0) (0,1,0)
    vals = [(2.0 ** -150, 0.0, 0.0), (1.0000000001, 0.0, 1e-50), (0.99999999995, 1.0000000001, 0.0),
            (0.0, 0.99999999999, 0.0)]
    assert all(x.f32_bits(v[a]) == x.f32_bits(f[a]) for v, f in zip(vals, fs) for a in range(3))
    out.append(('quad, the text\'s encoder choices', with_section(quad, x.encode_exact(vals, fs)), vals, fs))
    vals2 = [(0.0, 0.0, 0.0), (1.0000000001, 0.0, 0.0), (0.99999999995, 1.0000000001, 0.0), (0.0, 1.0, 0.0)]
    out.append(('quad, decimal 12, binary64, decimal 22 (width 0)',
                with_section(quad, x.encode_exact(vals2, fs, [12, 64, 22])), vals2, fs))
    # widths wider than the residuals need (64 on x, 1 on y where every residual is 0): x holds the
    # largest binary64 that still rounds to binary32 1.0 from above
    top = x.f64_of_bits(x.f64_bits(1.0) + (1 << 28) - 1)   # 1 + (2^28 - 1) ulps: below half a binary32 step
    assert x.f32_bits(top) == x.f32_bits(1.0)
    vals3 = [(0.0, 0.0, 0.0), (top, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 1.0, 0.0)]
    p3 = x.encode_exact(vals3, fs, [64, 64, 64])
    p3 = x.pack(list(p3[:3]), [[x.residual(v[a], f[a], 64) for v, f in zip(vals3, fs)] for a in range(3)], [64, 1, 0])
    out.append(('quad, binary64 in widths 64, 1, 0', with_section(quad, p3), vals3, fs))
    # 1 + 2^-24, halfway between binary32 1 and 1 + 2^-23: its nearest binary32 is 1 (ties to even),
    # the f a text such as 1.00000005960464477539062500001 has through its binary64
    vals4 = [(0.0, 0.0, 0.0), (1 + 2.0 ** -24, 0.0, 0.0), (1 - 2.0 ** -25, 1 + 2.0 ** -24, 0.0), (0.0, 1.0, 0.0)]
    assert all(x.f32_bits(v[a]) == x.f32_bits(f[a]) for v, f in zip(vals4, fs) for a in range(3))
    out.append(('quad, values halfway between two binary32 (ties to even)', with_section(quad, x.encode_exact(vals4, fs)),
                vals4, fs))
    # values near every f of other golden files (grid_normals_keep_order has an f = -0: N = 0 gives -0)
    for name, seed in (('l_tromino_keep_order', 1), ('polygons/polygons_mixed', 2),
                       ('normals/grid_normals_keep_order', 3), ('grid_3x2_comments', 4), ('tilted_noise', 5),
                       ('annulus_12x3', 6), ('texcoords/grid_seam_keep_order', 7)):
        path = os.path.join(root, 'testdata/golden', name + '.qsp')
        if not os.path.exists(path):
            expect(False, 'missing %s' % path)
            continue
        data = open(path, 'rb').read()
        fs = binary32_positions(data)
        vals = nearby(fs, seed)
        out.append((name, with_section(data, x.encode_exact(vals, fs)), vals, fs))
        if name == 'tilted_noise':   # every axis binary64; values halfway between two binary32
            out.append((name + ', all binary64', with_section(data, x.encode_exact(vals, fs, [64] * 3)), vals, fs))
            even = lambda f: x.f32_bits(f) & 1 == 0
            ties = [tuple(f[a] + ulp32(f[a]) / 2 if f[a] and even(f[a]) else f[a] for a in range(3)) for f in fs]
            out.append((name + ', values halfway above each f of even mantissa (to even: f)',
                        with_section(data, x.encode_exact(ties, fs)), ties, fs))
            v, a = next((v, a) for v in range(len(fs)) for a in range(3) if fs[v][a] and not even(fs[v][a]))
            odd = [list(f) for f in fs]
            odd[v][a] = fs[v][a] + ulp32(fs[v][a]) / 2
            out.append((name + ', a value halfway above an f of odd mantissa (to even: not f)',
                        with_section(data, x.encode_exact(odd, fs, [64] * 3)), None, fs))
    return out


FLT_MAX = g.bits_f32(0x7F7FFFFF)
OVERFLOW = FLT_MAX + 2.0 ** 103      # halfway between FLT_MAX and 2^128: rounds (to even) to infinity
DOUBLE_ROUNDED = (3799794560238578399, 643804029693342780, 1850666214957304859, 3621949200298330365,
                  975527355296720202, 1964449769089445720)   # N * 10^-19 whose binary64 is not that of
                                                              # the binary64 of N divided by 10^19


def crafted(qsp, tmp):
    """Files qsp compress --float32 writes for a 3x2 grid whose binary32 positions the golden files do
    not have, with a section of given modes put in: (name, bytes, values, binary32 positions) of the
    valid ones and (name, bytes) of the broken ones. Axis x: decimal with 19 decimals, N * 10^-19
    where rounding N to binary64 first would give another value; y: decimal with 0, N = 2^53 + 1 and
    2^53 + 3 (ties, to even: 2^53 and 2^53 + 4), -(2^53 + 1), 2^62 - 2^38 (the largest binary32 p
    below 2^62), +0 and -0 (N = 0); z: binary64, -0, the largest value below the one that rounds to
    binary32 infinity (over FLT_MAX), 1.49 * 2^-149 over 2^-149, 1e-50 over +0, -1e-50 over -0,
    2^62 + 2^10 over 2^62. Beside it, the grid with y = 2^62 at the third vertex (p = 2^62: y must
    be binary64; its variants make it decimal)."""
    rows = [(DOUBLE_ROUNDED[0], 2 ** 53 + 1, -0.0), (DOUBLE_ROUNDED[1], 2 ** 53 + 3, x.f64_of_bits(x.f64_bits(OVERFLOW) - 1)),
            (DOUBLE_ROUNDED[2], 2 ** 62 - 2 ** 38, 1.49 * 2.0 ** -149), (DOUBLE_ROUNDED[3], 0, 1e-50),
            (DOUBLE_ROUNDED[4], '-0', -1e-50), (DOUBLE_ROUNDED[5], -(2 ** 53 + 1), 2.0 ** 62 + 2 ** 10)]

    def vals(rows):
        return [(float('%de-19' % n), -0.0 if ny == '-0' else float(ny), z) for n, ny, z in rows]

    def grid(rows, name):
        obj, out = os.path.join(tmp, name + '.obj'), os.path.join(tmp, name + '.qsp')
        with open(obj, 'w') as o:
            for v in vals(rows):
                o.write('v %s\n' % ' '.join('%.9g' % g.bits_f32(x.f32_bits(t)) for t in v))
            o.write('f 1 2 5 4\nf 2 3 6 5\n')
        r = subprocess.run([qsp, 'compress', '-f', '-q', '--float32', '--positions-only', obj, out],
                           capture_output=True)
        if r.returncode:
            expect(False, 'qsp compress refuses %s: %s' % (obj, r.stderr.decode().strip()))
            return None
        data = open(out, 'rb').read()
        fs = binary32_positions(data)
        want = {tuple(x.f32_bits(t) for t in v): (v, row) for v, row in zip(vals(rows), rows)}
        got = [want.get(tuple(x.f32_bits(t) for t in f)) for f in fs]
        if None in got:
            expect(False, '%s: qsp compress --float32 wrote other binary32 positions' % name)
            return None
        return data, fs, got

    valid, broken = [], []
    a = grid(rows, 'crafted')
    if a:
        data, fs, got = a
        values = [v for v, _ in got]
        res = [[n - x.round_half_away(f[0] * 1e19) for f, (_, (n, _, _)) in zip(fs, got)],
               [(0 if ny == '-0' else ny) - x.round_half_away(f[1]) for f, (_, (_, ny, _)) in zip(fs, got)],
               [x.ord64(v[2]) - x.ord64(f[2]) for f, (v, _) in zip(fs, got)]]
        valid.append(('crafted grid', with_section(data, x.pack([19, 0, 64], res)), values, fs))
        k = next(i for i, (v, _) in enumerate(got) if v[2] == x.f64_of_bits(x.f64_bits(OVERFLOW) - 1))
        res[2][k] += 1
        broken.append(('crafted grid: z at the binary32 overflow boundary (rounds to infinity, not FLT_MAX)',
                       with_section(data, x.pack([19, 0, 64], res))))
    rows[2] = (DOUBLE_ROUNDED[2], 2 ** 62, rows[2][2])
    b = grid(rows, 'crafted_p')
    if b:
        data, fs, got = b
        values = [v for v, _ in got]
        valid.append(('crafted grid with y = 2^62', with_section(data, x.encode_exact(values, fs)), values, fs))
    return valid, broken


def decoded(data):
    """The decoded mesh's binary64 values, per output vertex before the order section (LAST)."""
    mesh = poly.decode_file(data)
    return mesh, x.LAST.get('values')


def reads_36(qsp):
    """Whether QSP says it reads format 3.6 (`qsp --version`: "reads 3.0 to 3.N")."""
    import re
    m = re.search(r'reads 3\.0 to 3\.(\d+)', subprocess.run([qsp, '--version'], capture_output=True,
                                                             text=True).stdout)
    return bool(m) and int(m.group(1)) >= 6


def test(root, qsp, tmp):
    cases = handmade(root)
    todo = []
    more = crafted(qsp, tmp) if qsp else ([], [])
    cases += more[0]
    def refused(what, bad):   # qsppoly.py must refuse it; qsp decompress too, below
        try:
            poly.decode_file(bad)
            expect(False, 'qsppoly.py does not refuse %s' % what)
        except g.FormatError:
            pass
        todo.append((what, bad, False, None))
    for what, bad in more[1]:
        refused(what, bad)
    for name, data, vals, fs in cases:
        if vals is None:   # a broken one of its own
            refused(name, data)
            continue
        try:
            mesh, got = decoded(data)
        except g.FormatError as e:
            expect(False, 'qsppoly.py refuses %s: %s' % (name, e))
            continue
        key = lambda vs: [tuple(x.f64_bits(t) for t in p) for p in vs]
        expect(key(got) == key(vals), 'qsppoly.py decodes %s to other values (first: %s)' % (
            name, next(((i, a, b) for i, (a, b) in enumerate(zip(got, vals)) if key([a]) != key([b])), None)))
        # the order section moved them with their vertices: each output vertex's value rounds to its f
        for p, v in zip(mesh[0], mesh[8]):
            if tuple(x.f32_bits(t) for t in v) != p:
                expect(False, '%s: an output vertex\'s values are another vertex\'s' % name)
                break
        todo.append((name, data, True, mesh))
        for what, bad, why in variants(data):
            if bad is None:
                print('exactgen: %s: %s: skipped, %s' % (name, what, why))
                continue
            refused('%s: %s' % (name, what), bad)
    if qsp is None:
        return len(todo)
    if not reads_36(qsp):
        print('exactgen: %s does not read format 3.6 yet: qsp decompress is not checked' % qsp)
        return len(todo)
    for i, (what, data, valid, mesh) in enumerate(todo):
        f, out = os.path.join(tmp, '%d.qsp' % i), os.path.join(tmp, '%d.obj' % i)
        open(f, 'wb').write(data)
        r = subprocess.run([qsp, 'decompress', '-f', f, '-o', out], capture_output=True)
        if not valid:
            expect(r.returncode != 0, 'qsp decompress does not refuse: %s' % what)
            continue
        expect(r.returncode == 0, 'qsp decompress refuses %s: %s' % (what, r.stderr.decode().strip()))
        if r.returncode == 0:
            bad = x.compare_written(mesh, x.read_mesh64(out), 'qsp decompress\'s output')
            expect(not bad, '%s: %s' % (what, bad))
    return len(todo)


def main():
    args = sys.argv[1:]
    if len(args) == 4 and args[0] == '--digits':
        digits_mesh(args[1], args[2], int(args[3]))
        return 0
    if len(args) == 2 and args[0] == '--tricky':
        tricky(args[1])
        return 0
    if len(args) == 4 and args[0] == '--put':
        open(args[3], 'wb').write(put(open(args[1], 'rb').read(), args[2]))
        return 0
    if args[:1] == ['--test'] and len(args) <= 2:
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
        with tempfile.TemporaryDirectory() as tmp:
            n = test(root, args[1] if len(args) == 2 else None, tmp)
        print('exactgen: %s' % ('%d failed' % len(FAILED) if FAILED else 'all hold (%d files)' % n))
        return 1 if FAILED else 0
    if len(args) == 2 and not args[0].startswith('-'):
        data = open(args[0], 'rb').read()
        os.makedirs(args[1], exist_ok=True)
        base = os.path.splitext(os.path.basename(args[0]))[0]
        for i, (what, bad, why) in enumerate(variants(data)):
            if bad is None:
                print('-\t%s: skipped, %s' % (what, why))
                continue
            path = os.path.join(args[1], '%s_broken_%02d.qsp' % (base, i))
            open(path, 'wb').write(bad)
            print('%s\t%s' % (path, what))
        return 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == '__main__':
    sys.exit(main())
