#!/usr/bin/env python3
"""The exact positions section (0x0a, format 3.6) of a .qsp file, written from format-spec/qsp_format.md
("Exact positions section") alone, without reading the codec's C++: the binary64 value of every output
vertex's coordinates, from the binary32 positions the geometry (and polygons) sections give and the
residuals this section holds.

decode_exact() is what qsppoly.py calls; encode_exact() is an encoder of the section that makes the
choices the text says the reference encoder makes (per axis decimal or binary64, the fewest bits), so
that a file's section can be checked byte for byte against it; read_mesh64(), compare_exact() and
compare_written() compare decoded values with the binary64 values a mesh file's text denotes and with
the text `qsp decompress` writes (the shortest text that reads back to each value).

Points where the text leaves a choice are named by the constants below the imports.
"""
import decimal
import math
import struct

import qspgeo as g

FormatError = g.FormatError
need = g.need

MODES = tuple(range(23)) + (64,)   # "modes": 0 to 22 decimal with that many decimals, 64 binary64
BINARY64 = 64
MAX_WIDTH = 64
P_LIMIT = 1 << 62                  # |p| < 2^62
N_LIMIT = 1 << 63                  # |N| < 2^63

SAME_F_BY_BITS = True      # "a value whose nearest binary32 is not f": compared as binary32 bits, so a
                           # value -0.0 over f = +0.0 (or +0.0 over -0.0) is refused; the text does
                           # not say whether -0 "is" +0 there
LAST = {}   # the last decode_exact() call's binary32 positions and values (before an order section)
ORD_OUT_OF_RANGE_REFUSED = True  # ord(f) + r outside [-2^63, 2^63 - 1] names no binary64: refused (the
                                 # text only says the value must be finite)


def f32_bits(x):
    """The binary32 nearest to binary64 x (ties to even; beyond the largest finite, an infinity), as
    bits."""
    return g.f32_bits_of_double(x)


def f64_bits(x):
    return struct.unpack('<Q', struct.pack('<d', x))[0]


def f64_of_bits(u):
    return struct.unpack('<d', struct.pack('<Q', u))[0]


def ord64(x):
    """ord(x): the bits as an unsigned integer u with the sign bit clear, -1 - (u - 2^63) with it set."""
    u = f64_bits(x)
    return u if u < 1 << 63 else -1 - (u - (1 << 63))


def unord64(o):
    """The binary64 whose ord is o (None if no binary64 has it)."""
    if not -(1 << 63) <= o < 1 << 63:
        return None
    return f64_of_bits(o if o >= 0 else (1 << 63) - 1 - o)


def round_half_away(p):
    """A binary64 p rounded to the nearest integer, halves away from zero, exactly."""
    n, d = abs(p).as_integer_ratio()
    m = (2 * n + d) // (2 * d)
    return -m if p < 0 else m


def zigzag(r):
    return 2 * r if r >= 0 else -2 * r - 1


def unzigzag(u):
    return u >> 1 if u % 2 == 0 else -((u + 1) >> 1)


def value_of(f, mode, r):
    """The value of a coordinate whose binary32 is f (a Python float) in mode `mode` with residual r:
    (value, None), or (None, why) when the text makes it a format error."""
    if mode == BINARY64:
        if ORD_OUT_OF_RANGE_REFUSED and unord64(ord64(f) + r) is None:
            return None, 'ord(f) + r = %d names no binary64' % (ord64(f) + r)
        x = unord64(ord64(f) + r)
        if not math.isfinite(x):
            return None, 'binary64 value %r is not finite' % x
    else:
        k = mode
        p = f * float(10 ** k)            # one binary64 multiplication; 10^k is exact for k <= 22
        if not abs(p) < P_LIMIT:          # (a NaN p fails too)
            return None, '|p| = |f * 10^%d| = %r is not below 2^62' % (k, abs(p))
        N = round_half_away(p) + r
        if not abs(N) < N_LIMIT:
            return None, '|N| = %d is not below 2^63' % abs(N)
        if N == 0:
            x = math.copysign(0.0, f)
        else:
            x = float('%de-%d' % (N, k))  # the binary64 nearest N * 10^-k, ties to even
    fb = f32_bits(f)
    if SAME_F_BY_BITS:
        same = f32_bits(x) == fb
    else:
        same = g.bits_f32(f32_bits(x)) == f
    if not same:
        return None, 'value %r rounds to binary32 0x%08x, not f = %r (0x%08x)' % (x, f32_bits(x), f, fb)
    return x, None


def decode_exact(payload, V, positions, quantized, minor):
    """The section's binary64 values, per output vertex (x, y, z), in the order of `positions` (the
    output vertices before an order section moves them, as binary32 values in Python floats). V is
    the output vertex count, quantized whether the geometry section is quantized, minor the file's
    minor version. Raises FormatError on anything the text refuses."""
    need(minor >= 6, 'section 0x0a (exact positions) is format 3.6\'s, and the file says it is 3.%d' % minor)
    need(not quantized, 'section 0x0a (exact positions) in a file whose geometry section is quantized')
    need(len(positions) == V, 'exact positions: %d positions for %d output vertices' % (len(positions), V))
    out = decode_block(payload, positions, 3, 'exact positions', 'vertex')
    LAST.update(positions=[tuple(p) for p in positions], values=out)
    return out


def decode_block(payload, fs, K, what, item='value'):
    """The exact positions section's layout with K axes over n = len(fs) values ("Exact values
    section" reuses it per kind): K modes, K widths, the n residuals of axis 0, then of axis 1, ...;
    each value from its component's binary32 fs[i][a] (a Python float) and its residual. Returns the
    binary64 values per item, a tuple of K each. Raises FormatError on anything the text refuses."""
    n = len(fs)
    need(len(payload) >= 2 * K, '%s: %d bytes, fewer than the %d of the modes and widths' % (what, len(payload), 2 * K))
    modes, widths = payload[0:K], payload[K:2 * K]
    for a in range(K):
        need(modes[a] in MODES, '%s: axis %d mode %d (neither 0..22 nor 64)' % (what, a, modes[a]))
        need(widths[a] <= MAX_WIDTH, '%s: axis %d width %d (above 64)' % (what, a, widths[a]))
    nbits = n * sum(widths)
    need(len(payload) - 2 * K == (nbits + 7) // 8,
         '%s: %d bytes of residuals, %d fields of %s bits need %d' % (
             what, len(payload) - 2 * K, n, '+'.join(map(str, widths)), (nbits + 7) // 8))
    bits = int.from_bytes(payload[2 * K:], 'little')   # bit i of the string: bit i % 8 of byte i // 8
    need(bits >> nbits == 0, '%s: a bit after the last residual is set' % what)
    out = [[None] * K for _ in range(n)]
    at = 0
    for a in range(K):
        B, mask = widths[a], (1 << widths[a]) - 1
        for v in range(n):
            r = unzigzag((bits >> at) & mask)
            at += B
            x, why = value_of(fs[v][a], modes[a], r)
            need(why is None, '%s: %s %d axis %d: %s' % (what, item, v, a, why))
            out[v][a] = x
    return [tuple(p) for p in out]


# ---------------- the reference encoder's choices ("The reference encoder chooses per axis") -------
def shortest_decimals(x):
    """The decimals of the shortest text that reads back to binary64 x (Python's repr is such a text):
    0 for an integer, 5 for 1e-05, 10 for 41.8544769287."""
    e = decimal.Decimal(repr(x)).normalize().as_tuple().exponent
    return max(0, -e)


def scaled(x, k):
    """x's shortest text times 10^k, an integer (k at least its decimals)."""
    d = decimal.Decimal(repr(x)).scaleb(k)
    assert d == d.to_integral_value()
    return int(d)


def residual(x, f, mode):
    """The residual that gives value x over binary32 f in mode `mode` (None if none fits)."""
    if mode == BINARY64:
        return ord64(x) - ord64(f)
    k = mode
    p = f * float(10 ** k)
    if not abs(p) < P_LIMIT:
        return None
    N = scaled(x, k)
    if not abs(N) < N_LIMIT:
        return None
    return N - round_half_away(p)


def width(rs):
    return max((zigzag(r).bit_length() for r in rs), default=0)


def choose_mode(xs, fs):
    """An axis's mode, as the text says the reference encoder chooses it: decimal with k the most
    decimals of the shortest texts of its values if k <= 22, every N fits and its width is not larger
    than binary64's; else binary64."""
    k = max((shortest_decimals(x) for x in xs), default=0)
    b64 = width([residual(x, f, BINARY64) for x, f in zip(xs, fs)])
    if k <= 22:
        rs = [residual(x, f, k) for x, f in zip(xs, fs)]
        if None not in rs and width(rs) <= b64:
            return k
    return BINARY64


def pack(modes, residuals, widths=None):
    """The payload: modes, widths (the fewest bits by default) and residuals[a][v] of each axis."""
    if widths is None:
        widths = [width(rs) for rs in residuals]
    bits, at = 0, 0
    for a in range(len(modes)):
        for r in residuals[a]:
            z = zigzag(r)
            assert z < 1 << widths[a], (r, widths[a])
            bits |= z << at
            at += widths[a]
    return bytes(modes) + bytes(widths) + bits.to_bytes((at + 7) // 8, 'little')


def encode_exact(values, fs, modes=None, K=3):
    """The section of binary64 values[v][a] over binary32 fs[v][a] (Python floats), with the reference
    encoder's choices, or the given modes; K axes (an exact values section's block: K components)."""
    if modes is None:
        modes = [choose_mode([v[a] for v in values], [f[a] for f in fs]) for a in range(K)]
    K = len(modes)
    residuals = [[residual(v[a], f[a], modes[a]) for v, f in zip(values, fs)] for a in range(K)]
    assert all(None not in rs for rs in residuals), 'a value this mode cannot give'
    return pack(modes, residuals)


def is_binary32(x):
    """Whether binary64 x is a binary32 (its nearest binary32 is x itself, sign of a zero included)."""
    return f64_bits(g.bits_f32(f32_bits(x))) == f64_bits(x)


def needs_section(values):
    """Whether values hold a coordinate that is not a binary32 (when the encoder writes the section)."""
    return any(not is_binary32(x) for p in values for x in p if not math.isnan(x))


# ---------------- comparisons ----------------
def read_mesh64(path):
    """Positions as the binary64 values their text denotes (Python's float() reads the nearest,
    ties to even), their texts, and faces (0-based), of an .obj, an .off or a .ply (binary64 data as
    it is; a binary32 property widened)."""
    if path.endswith('.ply'):
        return read_ply64(path)
    lines = open(path, 'rb').read().split(b'\n')
    pos, texts, faces = [], [], []
    if path.endswith('.off'):
        words = []
        for raw in lines:
            words.append(raw.split(b'#')[0].split())
        words = [w for w in words if w]
        need(words[0][0].endswith(b'OFF'), '%s: no OFF keyword' % path)
        head = words[0][1:] or words[1]
        body = words[1:] if words[0][1:] else words[2:]
        nv, nf = int(head[0]), int(head[1])
        for w in body[:nv]:
            texts.append(tuple(x.decode() for x in w[:3]))
            pos.append(tuple(float(x) for x in w[:3]))
        for w in body[nv:nv + nf]:
            d = int(w[0])
            faces.append([int(x) for x in w[1:1 + d]])
        return pos, texts, faces
    for raw in lines:
        w = raw.split()
        if not w or w[0].startswith(b'#'):
            continue
        if w[0] == b'v':
            texts.append(tuple(x.decode() for x in w[1:4]))
            pos.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == b'f':
            idx = [int(x.split(b'/')[0]) for x in w[1:]]
            faces.append([i - 1 if i > 0 else len(pos) + i for i in idx])
    return pos, texts, faces


PLY_TYPES = {b'char': 'b', b'int8': 'b', b'uchar': 'B', b'uint8': 'B', b'short': 'h', b'int16': 'h',
             b'ushort': 'H', b'uint16': 'H', b'int': 'i', b'int32': 'i', b'uint': 'I', b'uint32': 'I',
             b'float': 'f', b'float32': 'f', b'double': 'd', b'float64': 'd'}


def ply_header(data):
    """A PLY file's header: its elements as (name, count, [(property name, type words)]), its format
    word and the offset of the first byte after it (the test readers here and in qspvalues.py and
    colorsgen.py share it)."""
    end = data.index(b'end_header') + len(b'end_header')
    end = data.index(b'\n', end) + 1
    elements, fmt = [], None
    for line in data[:end].split(b'\n'):
        w = line.split()
        if w[:1] == [b'format']:
            fmt = w[1]
        elif w[:1] == [b'element']:
            elements.append((w[1], int(w[2]), []))
        elif w[:1] == [b'property']:
            elements[-1][2].append((w[-1], w[1:-1]))
    return elements, fmt, end


def read_ply64(path):
    """read_mesh64 of a PLY file (ascii or binary_little_endian; vertex x y z, face vertex_indices)."""
    data = open(path, 'rb').read()
    elements, fmt, end = ply_header(data)
    need(fmt in (b'ascii', b'binary_little_endian'), '%s: PLY format %s' % (path, fmt))
    pos, texts, faces = [], [], []
    at = end
    words = data[end:].split() if fmt == b'ascii' else None
    wi = 0

    def one(t):
        nonlocal at, wi
        if words is not None:
            wi += 1
            return words[wi - 1]
        c = PLY_TYPES[t]
        v = struct.unpack_from('<' + c, data, at)[0]
        at += struct.calcsize(c)
        return v

    for name, n, props in elements:
        for _ in range(n):
            row = {}
            for pname, ptype in props:
                if ptype[0] == b'list':
                    k = int(one(ptype[1]))
                    row[pname] = [int(one(ptype[2])) for _ in range(k)]
                else:
                    row[pname] = one(ptype[0])
            if name == b'vertex':
                xyz = [row[b'x'], row[b'y'], row[b'z']]
                texts.append(tuple(t.decode() if isinstance(t, bytes) else repr(float(t)) for t in xyz))
                pos.append(tuple(float(t) for t in xyz))
            elif name == b'face':
                faces.append(row.get(b'vertex_indices', row.get(b'vertex_index')))
    return pos, texts, faces


def exact_values(mesh):
    """The binary64 positions of a decoded mesh (qsppoly.decode_file's): its exact positions section's
    values, or its binary32 positions widened."""
    if len(mesh) > 8 and mesh[8] is not None:
        return mesh[8]
    return [tuple(g.bits_f32(u) for u in p) for p in mesh[0]]


def key(p):
    return tuple(f64_bits(x) for x in p)


def compare_exact(mesh, other, what, exact):
    """Every output vertex's binary64 position (bits, -0 and +0 apart) against other = read_mesh64's:
    index for index when exact, else as a multiset of positions and a multiset of faces as cycles of
    corner positions up to rotation."""
    pos = exact_values(mesh)
    faces = mesh[1]
    opos, _, ofaces = other
    bad = []
    if len(pos) != len(opos):
        return ['%d vertices, %s %d' % (len(pos), what, len(opos))]
    if exact:
        diff = [i for i in range(len(pos)) if key(pos[i]) != key(opos[i])]
        if diff:
            i = diff[0]
            bad.append('%d vertices\' binary64 positions differ from %s\'s (first: vertex %d, %r, there %r)' % (
                len(diff), what, i, pos[i], opos[i]))
        return bad
    if sorted(map(key, pos)) != sorted(map(key, opos)):
        a, b = sorted(map(key, pos)), sorted(map(key, opos))
        i = next(i for i in range(len(a)) if a[i] != b[i])
        bad.append('binary64 positions differ from %s\'s as multisets (first: %r, there %r)' % (
            what, tuple(map(f64_of_bits, a[i])), tuple(map(f64_of_bits, b[i]))))
        return bad

    def cycles(p, fs):
        return sorted(min(tuple(c[k:] + c[:k]) for k in range(len(c))) for c in ([key(p[v]) for v in f] for f in fs))

    if cycles(pos, faces) != cycles(opos, ofaces):
        bad.append('faces\' corner positions (binary64) differ from %s\'s' % what)
    return bad


def digits(text):
    """The significant digits of a number's text ('' for zero)."""
    t = text.lower().lstrip('+-')
    t = t.split('e')[0].replace('.', '')
    return t.strip('0')


SHORTEST = 'digits or characters'   # "the shortest text that reads back to it": the text does not say
                                    # shortest in what. A text passes with no more significant digits
                                    # than the shortest round trip's (Python's repr), or no more
                                    # characters than those digits in the shorter of fixed and
                                    # scientific notation (std::to_chars' choice: 2^62 as
                                    # 4611686018427387904, its exact digits, 19 characters where
                                    # 4.611686018427388e+18 has 21)


def shortest_chars(v):
    """Characters of the shortest round-trip digits of v in the shorter of fixed and scientific form."""
    t = repr(abs(v))
    d = decimal.Decimal(t).normalize()
    sign, ds, e = d.as_tuple()
    n = len(ds)
    if v == 0:
        return 1 + (math.copysign(1, v) < 0)
    fixed = n + e if e >= 0 else (max(n, -e) + 1 + (1 if -e >= n else 0))
    sci = n + (1 if n > 1 else 0) + 2 + max(2, len(str(abs(n - 1 + e))))   # e-05, as printf
    return min(fixed, sci) + (v < 0)


def compare_written(mesh, other, what):
    """The binary64 positions against what a decoder wrote (read_mesh64 of its output), index for
    index, each coordinate's text the shortest that reads back to the value (SHORTEST)."""
    bad = compare_exact(mesh, other, what, exact=True)
    pos = exact_values(mesh)
    _, texts, _ = other
    long = [(i, a, t) for i, p in enumerate(texts) for a, t in enumerate(p)
            if i < len(pos) and len(digits(t)) > len(digits(repr(pos[i][a])))
            and len(t) > shortest_chars(pos[i][a])]
    if long:
        i, a, t = long[0]
        bad.append('%d coordinates written longer than the shortest text, in digits and in characters (first: '
                   'vertex %d axis %d, %s where %r reads back)' % (len(long), i, a, t, pos[i][a]))
    return bad


def compare_encoder(data, secs, values):
    """The section against the reference encoder's choices as the text states them: byte for byte what
    encode_exact() writes (modes, fewest widths, residuals with a decimal N the value's shortest text)
    from the binary32 positions and values the last decode_exact() call saw, before the order section.
    data, values: unused but for a file without the section (nothing to compare)."""
    bad = []
    if 0x0a not in secs:
        return bad
    # (a section whose values are all binary32 is not flagged: the text says both "some coordinate's
    # value is not a binary32" and "whose text has more digits than binary32 holds", and qsp goes by the
    # text: 4611686018427387904, 2^62, gets a section; 3.4028235e38 alone, FLT_MAX's shortest text, none)
    fs, xs = LAST['positions'], LAST['values']
    mine = encode_exact(xs, fs)
    theirs = bytes(secs[0x0a])
    if mine != theirs:
        bad.append('the section is not the one the text\'s encoder choices give: modes %s widths %s, '
                   'the text\'s modes %s widths %s%s' % (
                       list(theirs[:3]), list(theirs[3:6]), list(mine[:3]), list(mine[3:6]),
                       ' (the residuals differ)' if mine[:6] == theirs[:6] else ''))
    return bad
