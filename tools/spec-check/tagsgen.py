#!/usr/bin/env python3
"""tagsgen.py: subdivision tags sections (qsp_format.md "Subdivision tags section") written from the
text, to test qsppoly.py's decoder of that section on payloads no qsp encoder writes.

usage: tagsgen.py [QSP]
       puts sections into testdata/golden/tags/cube_tags.qsp (no order section) and
       cube_tags_keep_order.qsp (one): valid ones (binary32 and binary64 floats, the extreme
       integers, the last vertex and face, a tag of another name beside an order section) that
       qsppoly.py must decode back, and ones breaking each rule the text names (counts 0 or past the
       bytes, an empty name or string, bytes <= 0x20 in one, a float width other than 4 and 8,
       non-finite floats, an odd crease, crease, corner and hole indices out of range, another name
       without an order section, bytes after the last tag, the section in a 3.3 file) that it must
       refuse. With QSP, also checks that `QSP decompress` refuses each broken file and writes the
       tags of each valid one. Exit 0 if all hold, else 1.
"""
import os
import struct
import subprocess
import sys
import tempfile

import qspgeo as g
import qsppoly as poly

FAILED = []


def expect(ok, what):
    if not ok:
        FAILED.append(what)
        print('tagsgen: ' + what)


def text(t):
    return g.varint(len(t)) + t


def zigzag(i):
    return 2 * i if i >= 0 else -2 * i - 1


def tag(name, ints=(), floats=(), strings=(), width=4, fmt=None):
    """One tag's bytes; fmt overrides the packing of the floats (for NaN and infinities as is)."""
    out = text(name) + g.varint(len(ints)) + g.varint(len(floats)) + g.varint(len(strings))
    out += b''.join(g.varint(zigzag(i)) for i in ints)
    if floats:
        out += bytes([width]) + b''.join(struct.pack(fmt or ('<f' if width == 4 else '<d'), x) for x in floats)
    return out + b''.join(text(s) for s in strings)


def section(*tags, count=None, extra=b''):
    return g.varint(len(tags) if count is None else count) + b''.join(tags) + extra


V, F = 8, 6   # the cube's
INF = float('inf')


def cases():
    """(what, payload, file with an order section?, valid?)"""
    ok = [
        ('settings, creases, corner, hole', section(
            tag(b'interpolateboundary', [2]), tag(b'crease', [0, 7, 7, 3], [2.5, 1e-3]),
            tag(b'corner', [V - 1], [10.0]), tag(b'hole', [F - 1]),
            tag(b'creasemethod', strings=[b'chaikin'])), False),
        ('binary64 floats, negative zero, a subnormal', section(
            tag(b'crease', [1, 2], [0.1, -0.0, 5e-324], width=8)), False),
        ('the extreme integers in a setting', section(
            tag(b'smoothtriangles', [-(1 << 63), (1 << 63) - 1, -1, 0])), False),
        ('a tag with nothing', section(tag(b'facevaryingpropagatecorners')), False),
        ('vertexedit beside an order section', section(
            tag(b'vertexedit', [2, 0, 3, 1, 0, 2, 1], [0.5, 0.25, -1.0], [b'value', b'set'])), True),
        ('another name of bytes above 0x7e beside an order section', section(
            tag(b'caf\xc3\xa9', [-5], strings=[b'\xff~'])), True),
    ]
    bad = [
        ('tag count 0', section(count=0), False),
        ('tag count past the bytes', section(tag(b'hole', [1]), count=99), False),
        ('empty name', section(tag(b'')), False),
        ('name with a space', section(tag(b'cr ease', [0, 1])), False),
        ('name with a tab', section(tag(b'corner\t', [0])), False),
        ('name with a NUL', section(tag(b'\x00hole', [0])), False),
        ('name past the section', g.varint(1) + g.varint(9) + b'crease', False),
        ('int count past the bytes', g.varint(1) + text(b'hole') + g.varint(9) + g.varint(0) + g.varint(0) + b'\x02',
         False),
        ('float count past the bytes', g.varint(1) + text(b'corner') + g.varint(1) + g.varint(50) + g.varint(0)
         + b'\x02\x04' + struct.pack('<f', 1.0), False),
        ('string count past the bytes', g.varint(1) + text(b'creasemethod') + g.varint(0) + g.varint(0) + g.varint(4)
         + text(b'x'), False),
        ('float width 0', section(tag(b'corner', [0], [1.0], width=0, fmt='<f')), False),
        ('float width 2', section(tag(b'corner', [0], [1.0], width=2, fmt='<e')), False),
        ('float width 16', g.varint(1) + text(b'corner') + g.varint(1) + g.varint(1) + g.varint(0) + g.varint(0)
         + bytes([16]) + struct.pack('<dd', 1.0, 1.0), False),
        ('binary32 NaN', section(tag(b'corner', [0], [float('nan')])), False),
        ('binary32 infinity', section(tag(b'corner', [0], [INF])), False),
        ('binary64 -infinity', section(tag(b'crease', [0, 1], [-INF], width=8)), False),
        ('floats past the section', section(tag(b'corner', [0], [1.0]))[:-1], False),
        ('empty string', section(tag(b'creasemethod', strings=[b''])), False),
        ('string with a space', section(tag(b'creasemethod', strings=[b'chai kin'])), False),
        ('string with a LF', section(tag(b'creasemethod', strings=[b'chaikin\n'])), False),
        ('odd crease', section(tag(b'crease', [0, 1, 2], [1.0])), False),
        ('crease vertex V', section(tag(b'crease', [0, V], [1.0])), False),
        ('corner vertex V', section(tag(b'corner', [V], [1.0])), False),
        ('corner vertex -1', section(tag(b'corner', [-1], [1.0])), False),
        ('hole face F', section(tag(b'hole', [F])), False),
        ('hole face F with an order section', section(tag(b'hole', [F])), True),
        ('vertexedit without an order section', section(tag(b'vertexedit', [0, 0, 3, 1], [1.0], [b'value', b'set'])),
         False),
        ('bytes after the last tag', section(tag(b'hole', [0]), extra=b'\x00'), False),
        ('non-minimal int', g.varint(1) + text(b'hole') + g.varint(1) + g.varint(0) + g.varint(0) + b'\x82\x00',
         False),
    ]
    return [(w, p, o, True) for w, p, o in ok] + [(w, p, o, False) for w, p, o in bad]


def with_tags(root, payload, order, minor=4):
    """The golden file with `payload` for its tags section, in a file of that minor version: today's
    golden, or where that has a symmetry section (3.17, valid only in a 3.17 file) the newest copy of
    an earlier version that has none."""
    import glob
    name = 'cube_tags_keep_order.qsp' if order else 'cube_tags.qsp'
    paths = [os.path.join(root, 'testdata/golden/tags', name)]
    paths += sorted(glob.glob(os.path.join(root, 'testdata/golden/v3.*/tags', name)),
                    key=lambda p: int(p.split('/v3.')[1].split('/')[0]), reverse=True)
    data = next((d for d in (open(p, 'rb').read() for p in paths) if 0x0f not in g.sections(d)), None)
    assert data is not None, 'no %s without a symmetry section' % name
    secs = g.sections(data)
    secs[0x08] = payload
    return g.container(data[:9] + bytes([minor]) + data[10:11], secs)


def main():
    if len(sys.argv) > 2 or sys.argv[1:2] and sys.argv[1].startswith('-'):
        print(__doc__, file=sys.stderr)
        return 2
    qsp = sys.argv[1] if len(sys.argv) == 2 else None
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
    todo = [(w, with_tags(root, p, o), v, p) for w, p, o, v in cases()]
    todo.append(('in a 3.3 file', with_tags(root, section(tag(b'hole', [0])), False, minor=3), False, None))
    with tempfile.TemporaryDirectory() as tmp:
        for i, (what, data, valid, payload) in enumerate(todo):
            try:
                mesh = poly.decode_file(data)
                expect(valid, 'qsppoly.py does not refuse: %s' % what)
            except g.FormatError as e:
                expect(not valid, 'qsppoly.py refuses %s: %s' % (what, e))
                mesh = None
            if mesh is not None:   # decoded back: the tags as written
                again = section(*[tag(n, ints, fl, st, w or 4) for n, ints, fl, st, w in mesh[6]])
                expect(again == payload, 'qsppoly.py decodes %s to other tags: %s' % (what, mesh[6]))
            if qsp is None:
                continue
            f, out = os.path.join(tmp, '%d.qsp' % i), os.path.join(tmp, '%d.obj' % i)
            open(f, 'wb').write(data)
            r = subprocess.run([qsp, 'decompress', '-f', f, '-o', out], capture_output=True)
            if not valid:
                expect(r.returncode != 0, 'qsp decompress does not refuse: %s' % what)
                continue
            expect(r.returncode == 0, 'qsp decompress refuses %s: %s' % (what, r.stderr.decode().strip()))
            if r.returncode == 0 and mesh is not None:
                try:
                    bad = poly.compare_tags(mesh, poly.read_obj_tags(out), 'qsp decompress\'s output', exact=True)
                except (g.FormatError, ValueError) as e:
                    bad = ['its output does not read back: %s' % e]
                expect(not bad, '%s: %s' % (what, bad))
    print('tagsgen: %s' % ('%d failed' % len(FAILED) if FAILED else 'all hold (%d sections)' % len(todo)))
    return 1 if FAILED else 0


if __name__ == '__main__':
    sys.exit(main())
