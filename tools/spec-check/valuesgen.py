#!/usr/bin/env python3
"""valuesgen.py: meshes whose texture coordinates, normals or colours binary32 does not hold, and
exact values sections (qsp_format.md "Exact values section", format 3.13) broken each way the text
names, to test qsppoly.py's decoder of that section (qspvalues.py) and qsp decompress.

usage: valuesgen.py --make DIR
       writes small meshes into DIR and prints a line `NAME<TAB>MESH<TAB>OPTIONS` for each file to
       encode: 2-, 3- and 1-component texture coordinates of 10 to 17 significant digits beside
       binary32 values, short decimals (0.1) and -0; normals of 17 digits; OBJ vertex colours of 12
       digits (rgb and rgba); a polygon mesh of triangles with all three; OFF vertex and face colours
       and a binary PLY with binary64 vertex and face colours; and a mesh whose values are all short
       decimals (no section); each with and without --keep-order.
       valuesgen.py --test FILE.qsp QSP TMPDIR
       FILE holds an exact values section: checks that qsppoly.py and `QSP decompress` both read FILE
       and FILE with its blocks rewritten in other modes and widths (binary64 and 64 bits, decimal with
       22 decimals where it holds), to the same values, and both refuse each variant breaking a rule
       the text names (kinds 0, a reserved kind bit, a kind whose array the mesh does not have, a block
       length past the section, a block a byte short or long, a width past the block, bytes after the
       last block, a value not rounding to its binary32, -0 over +0, a mode of 23, a padding bit, the
       section in a 3.12 file). Exit 0 if all hold, else 1.
"""
import os
import random
import struct
import subprocess
import sys

import qspexact as x
import qspgeo as g
import qsppoly as poly
import qspvalues as qv


# ---------------- meshes ----------------
def grid(n, m):
    pos = ['%d %d %s' % (i, j, '0.25' if (i + j) % 3 == 0 else '0') for j in range(m) for i in range(n)]
    faces = [[j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i] for j in range(m - 1) for i in range(n - 1)]
    return pos, faces


def triangles(n, m):
    pos, quads = grid(n, m)
    faces = []
    for q in quads:
        faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
    return pos, faces


def number(rng, kind):
    """A value's text: d10, d12, d17 (that many significant digits: binary32 holds none), f32 (a
    binary32's shortest text), short (0.1), int, negzero."""
    y = rng.uniform(-1.5, 1.5)
    if kind.startswith('d'):
        t = '%.*g' % (int(kind[1:]), y)
        return t
    if kind == 'f32':
        u = g.f32_bits_of_double(y)
        return str(qv.shortest32(u))
    if kind == 'short':
        return rng.choice(['0.1', '0.2', '0.3', '-0.7', '0.35'])
    if kind == 'int':
        return str(rng.randint(-3, 3))
    return '-0'


MIX = ['d10', 'd12', 'd17', 'd17', 'f32', 'short', 'int', 'negzero', 'd12', 'd10']


def obj(path, pos, faces, vt=None, vn=None, vc=None, per_corner=True):
    with open(path, 'w') as o:
        for i, p in enumerate(pos):
            o.write('v %s%s\n' % (p, ' ' + ' '.join(vc[i]) if vc else ''))
        for t in vt or []:
            o.write('vt %s\n' % ' '.join(t))
        for t in vn or []:
            o.write('vn %s\n' % ' '.join(t))
        k = 0
        for f in faces:
            cs = []
            for v in f:
                c = str(v + 1)
                if vt or vn:
                    c += '/' + (str(k % len(vt) + 1) if vt else '')
                if vn:
                    c += '/' + str(k % len(vn) + 1)
                cs.append(c)
                k += 1
            o.write('f %s\n' % ' '.join(cs))


def make(d):
    rng = random.Random(313)
    out = []

    def add(name, path, opts=''):
        out.append((name, path, opts))
        out.append((name + '_keep_order', path, ('--keep-order ' + opts).strip()))

    def vals(n, K, mix=MIX):
        return [tuple(number(rng, rng.choice(mix)) for _ in range(K)) for _ in range(n)]

    pos, faces = grid(4, 3)
    corners = 4 * len(faces)
    for K, name in ((2, 'uv2'), (3, 'uv3'), (1, 'uv1')):
        p = '%s/values_%s.obj' % (d, name)
        obj(p, pos, faces, vt=vals(corners - 5, K))
        add('values_' + name, p)
    p = '%s/values_normals.obj' % d
    obj(p, pos, faces, vn=vals(9, 3, ['d17', 'd17', 'f32', 'int', 'd12']))
    add('values_normals', p)
    for K, name in ((3, 'rgb'), (4, 'rgba')):
        p = '%s/values_%s.obj' % (d, name)
        obj(p, pos, faces, vc=vals(len(pos), K, ['d12', 'd12', 'f32', 'short', 'int']))
        add('values_' + name, p)
    tp, tf = triangles(4, 4)
    p = '%s/values_triangles.obj' % d
    obj(p, tp, tf, vt=vals(3 * len(tf) - 7, 2), vn=vals(11, 3, ['d17', 'f32']),
        vc=vals(len(tp), 3, ['d12', 'f32']))
    add('values_triangles', p)
    p = '%s/values_short.obj' % d     # all short decimals and binary32s: no section
    obj(p, pos, faces, vt=vals(corners, 2, ['f32', 'short', 'int']), vc=vals(len(pos), 3, ['short', 'int']))
    add('values_short', p)
    # OFF: vertex and face colours of 12 digits (a face colour of 1 and of 3 components)
    for Kf in (3, 1):
        p = '%s/values_off_%d.off' % (d, Kf)
        vc = vals(len(pos), 3, ['d12', 'f32', 'short'])
        fc = vals(len(faces), Kf, ['d12', 'd10', 'f32'] if Kf == 3 else ['int'])
        with open(p, 'w') as o:
            o.write('COFF\n%d %d 0\n' % (len(pos), len(faces)))
            for q, c in zip(pos, vc):
                o.write('%s %s\n' % (q, ' '.join(c)))
            for f, c in zip(faces, fc):
                o.write('%d %s %s\n' % (len(f), ' '.join(map(str, f)), ' '.join(c)))
        add('values_off_%d' % Kf, p)
    # binary PLY with binary64 vertex and face colours (every binary64, no text)
    p = '%s/values_ply.ply' % d
    head = ['ply', 'format binary_little_endian 1.0', 'element vertex %d' % len(pos), 'property float x',
            'property float y', 'property float z', 'property double red', 'property double green',
            'property double blue', 'element face %d' % len(faces), 'property list uchar int vertex_indices',
            'property double red', 'property double green', 'property double blue', 'end_header']
    body = bytearray(('\n'.join(head) + '\n').encode())
    for q in pos:
        body += struct.pack('<3f', *map(float, q.split()))
        body += struct.pack('<3d', *(rng.random() if k else float(rng.randint(0, 1)) for k in (1, 1, 0)))
    for f in faces:
        body += struct.pack('<B4i', 4, *f) + struct.pack('<3d', rng.random(), 0.5, rng.random())
    open(p, 'wb').write(bytes(body))
    add('values_ply', p)
    for name, path, opts in out:
        print('%s\t%s\t%s' % (name, path, opts))


# ---------------- variants of a file's section ----------------
def blocks(payload):
    """(kinds, [(bit, block)]) of a valid section."""
    kinds, at, out = payload[0], 1, []
    for b in range(4):
        if kinds >> b & 1:
            L, at = g.read_varint(payload, at)
            out.append((b, payload[at:at + L]))
            at += L
    return kinds, out


def unpack(block, n, K):
    """(modes, residuals per axis) of a valid block of n values."""
    ms, ws = list(block[:K]), list(block[K:2 * K])
    bits, at, rs = int.from_bytes(block[2 * K:], 'little'), 0, []
    for c in range(K):
        rs.append([])
        for _ in range(n):
            rs[-1].append(x.unzigzag((bits >> at) & ((1 << ws[c]) - 1)))
            at += ws[c]
    return ms, rs


def assemble(kinds, bl):
    return bytes([kinds]) + b''.join(g.varint(len(p)) + p for _, p in bl)


def reseal(data, secs, minor=None):
    return g.container(data[:9] + bytes([data[9] if minor is None else minor]) + data[10:11], secs)


def variants(data):
    """(what, file bytes, valid) of FILE's section rewritten."""
    secs = g.sections(data)
    sec = bytes(secs[0x0d])
    mesh = poly.decode_file(data)
    arrays = qv.arrays_of(mesh[4], mesh[7], mesh[9])
    kinds, bl = blocks(sec)
    out = [('the file itself', data, True)]

    def put(what, payload, valid=False, minor=None):
        out.append((what, reseal(data, {**secs, 0x0d: payload}, minor), valid))

    def fs_of(b):
        return [tuple(g.bits_f32(u) for u in v) for v in arrays[b][0]]

    # valid: other modes and widths
    for modes_of, what in ((lambda K: [64] * K, 'binary64'), (lambda K: [22] * K, 'decimal with 22 decimals')):
        nb, ok = [], True
        for b, p in bl:
            K = arrays[b][1]
            ms = modes_of(K)
            rs = [[x.residual(v[a], f[a], ms[a]) for v, f in zip(mesh[10][b], fs_of(b))] for a in range(K)]
            if any(None in r or any(abs(y) >= 1 << 62 for y in r) for r in rs):
                ok = False
                break
            nb.append((b, x.pack(ms, rs)))
        if ok:
            put('blocks in %s' % what, assemble(kinds, nb), True)
    b0, p0 = bl[0]
    K0 = arrays[b0][1]
    rs0 = [[x.residual(v[a], f[a], 64) for v, f in zip(mesh[10][b0], fs_of(b0))] for a in range(K0)]
    put('the first block in binary64, widths 64', assemble(kinds, [(b0, x.pack([64] * K0, rs0, [64] * K0))] + bl[1:]), True)
    # refused
    put('kinds 0 (the blocks after it)', bytes([0]) + sec[1:])
    put('kinds 0 alone', bytes([0]))
    put('an empty section', b'')
    for bit in (4, 7):
        put('reserved kind bit %d' % bit, bytes([kinds | 1 << bit]) + sec[1:])
    for b in range(4):
        if arrays[b] is None:
            K = 3
            extra = bytes([64] * K + [0] * K)   # a block of widths 0: no residuals
            nb = sorted(bl + [(b, extra)])
            put('kind %d (%s), which the mesh does not have' % (b, qv.KINDS[b]), assemble(kinds | 1 << b, nb))
    rest = len(sec) - 1 - len(g.varint(len(p0)))
    put('a block length past the section', bytes([kinds]) + g.varint(rest + 1) + sec[1 + len(g.varint(len(p0))):])
    put('a block length varint running past the section', bytes([kinds, 0x80]))
    put('the first block a byte short', assemble(kinds, [(b0, p0[:-1])] + bl[1:]))
    put('the first block a byte long', assemble(kinds, [(b0, p0 + b'\0')] + bl[1:]))
    if len(arrays[b0][0]) > 0:
        wider = bytearray(p0)
        wider[K0] += 1
        put('a width one more than the block holds', assemble(kinds, [(b0, bytes(wider))] + bl[1:]))
    put('a byte after the last block', sec + b'\0')
    put('the first kind\'s block left out', assemble(kinds, bl[1:]) if len(bl) > 1 else bytes([kinds]))
    put('the section in a 3.12 file', sec, minor=12)
    bad_mode = bytearray(p0)
    bad_mode[0] = 23
    put('a mode of 23', assemble(kinds, [(b0, bytes(bad_mode))] + bl[1:]))
    bad_width = bytearray(p0)
    bad_width[K0] = 65
    put('a width of 65', assemble(kinds, [(b0, bytes(bad_width))] + bl[1:]))
    nbits = len(arrays[b0][0]) * sum(p0[K0:2 * K0])
    if nbits % 8:
        pad = bytearray(p0)
        pad[-1] |= 0x80
        put('a padding bit set', assemble(kinds, [(b0, bytes(pad))] + bl[1:]))
    # a value that does not round to its binary32: one residual far off, in binary64
    rs = [list(r) for r in rs0]
    rs[0][0] += 1 << 40
    put('a value not rounding to its binary32 (binary64, 2^40 steps off)',
        assemble(kinds, [(b0, x.pack([64] * K0, rs))] + bl[1:]))
    for b, p in bl:   # a decimal axis's N moved by a hundredth
        K, n = arrays[b][1], len(arrays[b][0])
        ms, rs = unpack(p, n, K)
        fs = fs_of(b)
        axes = [(i, c) for c in range(K) if ms[c] < 64 and ms[c] >= 2 for i in range(n) if abs(fs[i][c]) < 1e3]
        if axes:
            i, c = axes[0]
            rs[c][i] += 10 ** ms[c] // 100
            put('a value not rounding to its binary32 (decimal, N a hundredth off)',
                assemble(kinds, [(d, x.pack(ms, rs) if d == b else q) for d, q in bl]))
            break
    for b, p in bl:   # -0 over an f of +0
        K, n = arrays[b][1], len(arrays[b][0])
        fs = fs_of(b)
        zero = [(i, c) for i in range(n) for c in range(K) if x.f64_bits(fs[i][c]) == 0]
        if zero:
            i, c = zero[0]
            rb = [[x.residual(v[d], f[d], 64) for v, f in zip(mesh[10][b], fs)] for d in range(K)]
            rb[c][i] = -1
            put('-0 over an f of +0 (%s)' % qv.KINDS[b],
                assemble(kinds, [(d, x.pack([64] * K, rb) if d == b else q) for d, q in bl]))
            break
    return out


def refusals(path, qsp, tmp):
    data = open(path, 'rb').read()
    ref = poly.decode_file(data)
    failed = []
    for i, (what, b, valid) in enumerate(variants(data)):
        try:
            mesh = poly.decode_file(b)
            ok, why = True, ''
            if valid:
                diff = [k for k in range(4) if (mesh[10][k] is None) != (ref[10][k] is None) or
                        mesh[10][k] is not None and [qv.key(v) for v in mesh[10][k]] != [qv.key(v) for v in ref[10][k]]]
                if diff:
                    failed.append('qsppoly.py decodes %s to other values (%s)' % (what, qv.KINDS[diff[0]]))
        except g.FormatError as e:
            ok, why = False, str(e)
        if ok != valid:
            failed.append('qsppoly.py %s %s%s' % ('refuses' if valid else 'does not refuse', what,
                                                  ': ' + why if why else ''))
        f = '%s/values_case_%d.qsp' % (tmp, i)
        suffix = '.off' if '_off' in os.path.basename(path) or '_ply' in os.path.basename(path) else '.obj'
        open(f, 'wb').write(b)
        r = subprocess.run([qsp, 'decompress', '-f', f, '-o', f + suffix], capture_output=True, text=True)
        if (r.returncode == 0) != valid:
            failed.append('qsp decompress %s %s%s' % ('refuses' if valid else 'does not refuse', what,
                                                      ': ' + r.stderr.strip() if r.stderr.strip() else ''))
        elif valid:
            bad = qv.compare_written(poly.decode_file(b), f + suffix)
            failed += ['qsp decompress of %s: %s' % (what, x) for x in bad]
    return failed


def main():
    args = sys.argv[1:]
    if args[:1] == ['--make']:
        make(args[1])
        return 0
    if args[:1] == ['--test']:
        failed = refusals(args[1], args[2], args[3])
        for f in failed:
            print('valuesgen: %s: %s' % (args[1], f), file=sys.stderr)
        return 1 if failed else 0
    print(__doc__, file=sys.stderr)
    return 2


if __name__ == '__main__':
    sys.exit(main())
