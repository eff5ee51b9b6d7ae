#!/usr/bin/env python3
"""labelgen.py: face labels sections (qsp_format.md "Face labels section") written by an encoder from
the text, to test qsppoly.py's decoder of that section on payloads no qsp encoder writes.

usage: labelgen.py IN.obj OUT.obj SEED
       IN with o, g, usemtl, s and mtllib statements among its faces, for check.sh: faces before any
       statement of a kind, runs, names taken again after others, a bare g (the empty name), g with
       several names apart by tabs and spaces, s off, 0 and numbers, names no face takes (a g another
       g follows, a usemtl after the last face) and two mtllib lines.
       labelgen.py --test [QSP]
       encodes label streams (runs, faces without a label, earlier names, names no face takes,
       material libraries) and checks that qsppoly.py decodes each back; breaks each rule the text
       names (reserved bits, kinds 0, counts past the bytes, CR or LF in a name, two equal names, a
       new name past N, an earlier name r >= R, bytes after the stream, the section in a 3.2 file)
       and checks that qsppoly.py refuses it; adds a section to golden files (one with an order
       section) and checks that each output face keeps the labels of its canonical face. With QSP,
       also checks that `QSP decompress` refuses each broken section in a file and writes the labels
       of each valid one (as a multiset of faces with their labels). Exit 0 if all hold, else 1.
"""
import os
import sys

import qspgeo as g
import qsppoly as poly


def symbols(labels):
    """Per face the first rule of the text that codes its label (an index or None): ('same',),
    ('new',), ('none',) or ('earlier', r); names numbered by the first face that takes them."""
    out, m, p = [], 0, None
    number = {}
    for x in labels:
        if x == p:
            out.append(('same',))
        elif x is not None and x not in number:
            number[x] = m
            m += 1
            out.append(('new',))
        elif x is None:
            out.append(('none',))
        else:
            i, q = number[x], None if p is None else number[p]
            out.append(('earlier', i if q is None or i < q else i - 1))
        p = x
    return out, number


def code_kind(enc, syms):
    """One kind's symbols, its models fresh ("The stream")."""
    T, earlier = g.Table(), g.Table()
    c, p_named = 0, False   # p_named: the previous face has a name
    for s in syms:
        enc.bit(T['same', c], int(s[0] == 'same'))
        if s[0] == 'same':
            c = 1
            continue
        c = 0
        enc.bit(T['is_new'], int(s[0] == 'new'))
        if s[0] == 'new':
            p_named = True
            continue
        if p_named:
            enc.bit(T['is_none'], int(s[0] == 'none'))
        if s[0] == 'none':
            p_named = False
            continue
        enc.integer(earlier, s[1])
        p_named = True


def text(t):
    return g.varint(len(t)) + t


def texts(ts, front):
    """A list's texts, plainly or front-coded (kinds bit 5: each the bytes it shares with the one
    before, then the rest)."""
    out, before = b'', b''
    for t in ts:
        if front:
            k = len(os.path.commonprefix([t, before]))
            out += g.varint(k) + text(t[k:])
        else:
            out += text(t)
        before = t
    return out


def payload(kinds, names, syms, libraries=(), extra=b''):
    """A section: the kinds byte, each present kind's names (after its count), the libraries and
    the stream of each present kind's symbols."""
    out = bytearray([kinds])
    front = bool(kinds & 32)
    for k in range(4):
        if kinds >> k & 1:
            out += g.varint(len(names[k])) + texts(names[k], front)
    if kinds & 16:
        out += g.varint(len(libraries)) + texts(libraries, front)
    enc = g.RangeEncoder()
    for k in range(4):
        if kinds >> k & 1:
            code_kind(enc, syms[k])
    return bytes(out) + enc.finish() + extra


def section(per_kind, unused=None, libraries=(), front=False):
    """The section of these labels: per_kind {k: per face a name or None}, unused {k: names no face
    takes, in mesh order}; as the text's encoder numbers and codes them (front-coded if front)."""
    kinds = sum(1 << k for k in per_kind) | (16 if libraries else 0) | (32 if front else 0)
    names, syms = {}, {}
    for k, labels in per_kind.items():
        syms[k], number = symbols(labels)
        names[k] = sorted(number, key=number.get) + list((unused or {}).get(k, []))
    return payload(kinds, names, syms, libraries)


FAILED = []


def expect(ok, what):
    if not ok:
        FAILED.append(what)
        print('labelgen: FAILED: %s' % what, file=sys.stderr)


def roundtrip(per_kind, F, unused=None, libraries=()):
    b = section(per_kind, unused, libraries)
    labels, names, libs = poly.decode_labels(b, F)
    got = {k: [None if x is None else names[k][x] for x in labels[k]] for k in labels}
    expect(got == per_kind, 'round trip of %s' % per_kind)
    expect(libs == list(libraries), 'libraries %r' % (libraries,))
    for k in per_kind:
        expect(set(names[k]) - set(per_kind[k]) == set((unused or {}).get(k, [])), 'unused names of kind %d' % k)
    return b


def refused(b, F, what):
    try:
        poly.decode_labels(b, F)
    except g.FormatError:
        return
    expect(False, 'not refused: %s' % what)


def test_payloads():
    A, B, C = b'a', b'b b', b'c'
    roundtrip({0: [A] * 5}, 5)
    roundtrip({1: [None, None, A, A, B, None, A, C, B, B, A, None]}, 12, {1: [b'default', b'']})
    roundtrip({2: [A, B, C, A, B, C, C, None, C]}, 9, libraries=(b'x.mtl', b'y y.mtl'))
    roundtrip({0: [A, A, B], 1: [None, B, B], 2: [C, A, None], 3: [b'1', b'off', b'1']}, 3,
              {3: [b'2']}, (b'',))
    roundtrip({3: [None] * 4}, 4, {3: [b'off']})      # a kind no face takes
    roundtrip({1: [b''] * 3}, 3)                     # a bare g: the empty name
    b = section({}, libraries=(b'm.mtl',))             # libraries alone: no symbol, no stream byte
    expect(b == bytes([16, 1, 5]) + b'm.mtl', 'libraries alone: %r' % b)
    expect(poly.decode_labels(b, 7) == ({}, {}, [b'm.mtl']), 'libraries alone')
    roundtrip({1: [A, B] * 300 + [None] * 50 + [C, A, B, C] * 40}, 810)   # long runs: models adapt
    roundtrip({0: [], 1: []}, 0, {0: [A], 1: [B, C]})   # no faces

    good = section({1: [A, B, None]}, libraries=(b'l',))
    poly.decode_labels(good, 3)
    refused(bytes([0x40 | good[0]]) + good[1:], 3, 'reserved bit 6')
    # front-coded names (kinds bit 5, from 3.9): shared prefixes, refused in an older file, a shared
    # length past the text before it, and the 64-bytes-a-byte bound
    J = [b'joint-l-toe-1', b'joint-l-toe-2', b'joint-r', b'helper', b'helper-x']
    fc = section({1: J + [None]}, libraries=(b'lib/a.mtl', b'lib/b.mtl'), front=True)
    labels, names, libs = poly.decode_labels(fc, 6)
    expect(names[1] == J and libs == [b'lib/a.mtl', b'lib/b.mtl'], 'front-coded names %r %r' % (names, libs))
    expect(len(fc) < len(section({1: J + [None]}, libraries=(b'lib/a.mtl', b'lib/b.mtl'))), 'front coding pays')
    try:
        poly.decode_labels(fc, 6, minor=8)
        expect(False, 'front-coded names in a 3.8 file decoded')
    except g.FormatError:
        pass
    refused(bytes([0x22, 1, 1, 1]) + A + fc[-1:], 1, 'a first name sharing a byte')
    # 5,001 names of 10,000 shared bytes and 3 more cost 6 bytes each: ~50 MB of text from ~40 kB
    stem = b'x' * 10000
    many = [stem + bytes([65 + i % 26, 65 + i // 26 % 26, 65 + i // 676]) for i in range(5000)]
    refused(section({0: [stem]}, {0: many}, front=True), 1, 'front-coded texts past 64 bytes a section byte')
    refused(bytes([0x82]) + good[1:], 3, 'reserved bit 7')
    refused(bytes([0]) + good[1:], 3, 'kinds 0')
    refused(b'', 3, 'empty section')
    refused(bytes([2, 3, 1]) + A, 3, 'name count past the bytes')
    refused(bytes([2, 1, 5]) + A, 3, 'name past the bytes')
    refused(payload(16, {}, {}, ()), 0, 'library count 0')
    refused(bytes([16, 3, 1]) + A, 0, 'library count past the bytes')
    refused(payload(2, {1: [b'a\nb']}, {1: [('new',)]}), 1, 'LF in a name')
    refused(payload(2, {1: [b'a\r']}, {1: [('new',)]}), 1, 'CR in a name')
    refused(payload(16, {}, {}, (b'x\n',)), 0, 'LF in a library')
    refused(payload(1, {0: [A, A]}, {0: [('new',), ('new',)]}), 2, 'two equal names')
    poly.decode_labels(payload(1, {0: [A, B]}, {0: [('new',), ('new',)]}), 2)
    poly.decode_labels(payload(3, {0: [A], 1: [A]}, {0: [('new',)], 1: [('new',)]}), 1)  # equal names, two kinds
    refused(payload(1, {0: [A]}, {0: [('new',), ('new',)]}), 2, 'is_new with m = N')
    refused(payload(1, {0: []}, {0: [('new',)]}), 1, 'is_new with N = 0')
    poly.decode_labels(payload(1, {0: [A, B]}, {0: [('new',), ('new',), ('earlier', 0)]}), 3)
    refused(payload(1, {0: [A, B]}, {0: [('new',), ('new',), ('earlier', 1)]}), 3, 'r = R after a name')
    refused(payload(1, {0: [A]}, {0: [('earlier', 0)]}), 1, 'earlier with m = 0')
    poly.decode_labels(payload(1, {0: [A, B]}, {0: [('new',), ('none',), ('earlier', 0)]}), 3)
    refused(payload(1, {0: [A, B]}, {0: [('new',), ('none',), ('earlier', 1)]}), 3, 'r = R after none')
    poly.decode_labels(payload(1, {0: [A, B, C]}, {0: [('new',), ('new',), ('new',), ('earlier', 1)]}), 4)
    refused(payload(1, {0: [A, B, C]}, {0: [('new',), ('new',), ('new',), ('earlier', 2)]}), 4, 'r = R = m - 1')
    refused(good + b'\0', 3, 'a byte after the stream')
    refused(section({1: [A, B, None]}), 2, 'symbols for fewer faces than coded')
    refused(section({}, libraries=(b'l',)) + b'\1', 1, 'a stream byte with no kind present')
    # the non-first rules an encoder would not use still decode: same coded as earlier
    labels, names, _ = poly.decode_labels(payload(1, {0: [A, B]}, {0: [('new',), ('new',), ('earlier', 0), ('earlier', 0)]}), 4)
    expect(labels[0] == [0, 1, 0, 1], 'earlier without p: %s' % labels[0])


def with_labels(path, make, minor=3):
    """The golden file at path with a face labels section made by make(faces before the order
    section, positions) and its minor version set."""
    data = open(path, 'rb').read()
    secs = g.sections(data)
    pos, faces, _ = poly.canonical_mesh(data, secs)
    secs[0x07] = make(faces, pos)
    if 0x0c in secs and minor >= 3:   # a polygon golden with interior positions (3.12) stays 3.12
        minor = max(minor, 12)
    return g.container(data[:9] + bytes([minor]) + data[10:11], secs)


def test_files(root):
    def by_corners(faces, pos):   # each face's name: its corners' positions, so renumbering shows
        names = [b' '.join(b'%08x' % u for v in sorted(f, key=lambda v: pos[v]) for u in pos[v]) for f in faces]
        return section({0: names, 2: [None] + names[1:]}, libraries=(b'a.mtl',))

    for name in ('l_tromino_keep_order', 'quad', 'polygons/polygons_mixed', 'texcoords/grid_seam_keep_order',
                 'texcoords/polygon_uv'):
        path = os.path.join(root, 'testdata/golden', name + '.qsp')
        if not os.path.exists(path):
            expect(False, 'missing %s' % path)
            continue
        data = with_labels(path, by_corners)
        pos, faces, _, _, _, labels = poly.decode_file(data)[:6]
        want = [b' '.join(b'%08x' % u for v in sorted(f, key=lambda v: pos[v]) for u in pos[v]) for f in faces]
        expect(labels['faces'][0] == want, '%s: a face has another face\'s object' % name)
        mats = labels['faces'][2]
        expect(mats.count(None) == 1 and all(m is None or m == o for o, m in zip(want, mats)),
               '%s: a face has another face\'s material' % name)
        expect(labels['libraries'] == [b'a.mtl'], '%s: libraries' % name)
        try:
            poly.decode_file(with_labels(path, by_corners, minor=2))
            expect(False, '%s: section 0x07 in a 3.2 file not refused' % name)
        except g.FormatError:
            pass
    try:   # a required tag past those the text defines
        path = os.path.join(root, 'testdata/golden/quad.qsp')
        data = open(path, 'rb').read()
        secs = g.sections(data)
        secs[0x7F] = b''
        poly.decode_file(g.container(data[:9] + bytes([3]) + data[10:11], secs))
        expect(False, 'unknown required section 0x7f not refused')
    except g.FormatError:
        pass


POOL = {b'o': [b'body', b'head', b'Hand.L'], b'g': [b'', b'arm', b'leg\t left', b'arm  leg', b'torso'],
        b'usemtl': [b'skin', b'cloth', b'mat.001'], b's': [b'off', b'1', b'2', b'0']}


def sprinkle(src, out, seed):
    import random
    random.seed(seed)
    lines = open(src, 'rb').read().split(b'\n')
    w = open(out, 'wb')
    w.write(b'mtllib first.mtl\n')
    nf = 0
    for line in lines:
        if line.startswith(b'f '):
            nf += 1
            if nf == 30:
                w.write(b'g unused\n')       # a name no face takes: another g follows at once
                w.write(b'g arm\n')
            elif nf == 60:
                w.write(b'mtllib second one.mtl\n')
            elif nf > 12 and random.random() < 0.2:   # the first faces take no label
                kw = random.choice(list(POOL))
                name = random.choice(POOL[kw])
                w.write(kw + (b' ' + name if name else b'') + b'\n')
        w.write(line + (b'\n' if line else b''))
    w.write(b'usemtl trailing\n')              # after the last face: no face takes it


def cases(F):
    """(what, section, valid?) over F faces, for the reference decoder."""
    A, B, C = b'a', b'b', b'c'
    third = F // 3
    first = [None] * third + [A] * third + [B] * (F - 2 * third)
    alt = [A, B, C] * (F // 3) + [A] * (F % 3)
    yield 'runs, names no face takes, libraries', section({1: first}, {1: [b'unused']}, (b'x.mtl',)), True
    yield 'every kind', section({0: alt, 1: first, 2: alt[::-1], 3: [b'1'] * F}, {3: [b'off']}), True
    yield 'libraries alone', section({}, libraries=(b'l1', b'l 2')), True
    yield 'same coded as earlier', payload(1, {0: [A, B]}, {0: [('new',), ('new',)] + [('earlier', 0), ('earlier', 0)] * ((F - 2) // 2)
                                                              + [('earlier', 0)] * (F % 2)}), True
    good = section({1: first}, libraries=(b'l',))
    yield 'reserved bit 5', bytes([0x22]) + good[1:], False
    yield 'kinds 0', bytes([0]) + good[1:], False
    yield 'name count past the bytes', bytes([2, 9, 1]) + A, False
    yield 'library count 0', bytes([16, 0]), False
    yield 'LF in a name', payload(2, {1: [b'a\nb']}, {1: [('new',)] + [('same',)] * (F - 1)}), False
    yield 'CR in a library', payload(16, {}, {}, (b'x\r',)), False
    yield 'two equal names', payload(1, {0: [A, A]}, {0: [('new',)] * 2 + [('same',)] * (F - 2)}), False
    yield 'is_new with m = N', payload(1, {0: [A]}, {0: [('new',)] * 2 + [('same',)] * (F - 2)}), False
    yield 'r = R', payload(1, {0: [A, B]}, {0: [('new',), ('new',), ('earlier', 1)] + [('same',)] * (F - 3)}), False
    yield 'earlier with m = 0', payload(1, {0: [A]}, {0: [('earlier', 0)] + [('same',)] * (F - 1)}), False
    yield 'a byte after the stream', good + b'\0', False


def test_qsp(qsp, root):
    import subprocess
    import tempfile
    path = os.path.join(root, 'testdata/golden/l_shape.qsp')
    data = open(path, 'rb').read()
    F = g.counts(g.sections(data)[1])[1]
    with tempfile.TemporaryDirectory() as tmp:
        todo = [(w, s_, v, 3) for w, s_, v in cases(F)] + [('in a 3.2 file', section({0: [b'a'] * F}), False, 2)]
        for i, (what, sec, valid, minor) in enumerate(todo):
            f = os.path.join(tmp, '%d.qsp' % i)
            out = os.path.join(tmp, '%d.obj' % i)
            open(f, 'wb').write(with_labels(path, lambda faces, pos: sec, minor))
            r = subprocess.run([qsp, 'decompress', '-f', f, '-o', out], capture_output=True)
            if not valid:
                expect(r.returncode != 0, 'qsp decompress does not refuse: %s' % what)
                continue
            expect(r.returncode == 0, 'qsp decompress refuses %s: %s' % (what, r.stderr.decode().strip()))
            if r.returncode == 0:
                bad = poly.compare_labels(poly.decode_file(open(f, 'rb').read()), poly.read_obj_labels(out),
                                          'qsp decompress\'s output', exact=False, unused=False)
                expect(not bad, '%s: %s' % (what, bad))


def main():
    if len(sys.argv) == 4:
        sprinkle(sys.argv[1], sys.argv[2], int(sys.argv[3]))
        return 0
    if sys.argv[1:2] != ['--test'] or len(sys.argv) > 3:
        print(__doc__, file=sys.stderr)
        return 2
    test_payloads()
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
    test_files(root)
    if len(sys.argv) == 3:
        test_qsp(sys.argv[2], root)
    print('labelgen: %s' % ('%d failed' % len(FAILED) if FAILED else 'all hold'))
    return 1 if FAILED else 0


if __name__ == '__main__':
    sys.exit(main())
