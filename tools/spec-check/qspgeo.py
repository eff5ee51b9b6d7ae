#!/usr/bin/env python3
"""Geometry-section decoder for .qsp format 3.0, written from format-spec/geometry_section.md and
format-spec/qsp_format.md alone.

An independent reviewer rewrote it for 3.0 from the text without reading the codec's C++ (the 2.x
decoder it replaces was written the same way): the section's tools byte names the tools, and every
combination of them decodes. check.sh runs it over the golden files and fresh encodes, so the text
cannot drift from the reference decoder unnoticed.

usage: qspgeo.py [--dumped-stencils] FILE.qsp PREFIX
       builds FILE's coding order and stencils from its topology section (qsplayout.py, from the text
       too) and compares them with the reference's in PREFIX.stencil; decodes the geometry with its
       own stencils (with the reference's if --dumped-stencils) and compares with PREFIX.pos (the
       reference decoder's float bits, canonical order). Both files come from dump_stencils. Exit 0
       if the stencils agree and every coordinate matches bit for bit, else 1.
       qspgeo.py --recode FILE.qsp OUTDIR [TOOLS...]
       writes FILE with its geometry coded again under each tools byte (all 32 by default, 64 with
       a symmetry section: mirror prediction too), same
       header and values, by an encoder written from the same text (qsp_format.md "Entropy coding"):
       the reference decoder must read each to FILE's positions, which checks every tool
       combination whether or not the reference encoder ever writes it.
The stencil file gives, per coding position k: coding[k], 19 vertex fields (FIELDS, -1 = absent),
far_dist, e_dist, n_dist, xnum, xden.

Section names in comments ("Header", "Blend", ...) are those of geometry_section.md.
"""
import math
import struct
import sys

NONE = -1
FIELDS = ['w', 'ww', 's', 'sw', 'far', 'e', 'es', 'n', 'nw', 'o', 'ow', 'ofar', 'x0', 'x1', 'x2',
          'se', 'ss', 'sww', 'ssw']

# tools byte ("Header", tools table)
REPEATS, LAYOUT_ORDER, CHAINING, CELL_SHAPES, MIXING, MIRROR = 1, 2, 4, 8, 16, 32

U32_MAX = (1 << 32) - 1


class FormatError(Exception):
    pass


def need(cond, what):
    if not cond:
        raise FormatError(what)


def bit_width(u):
    assert u >= 0
    return u.bit_length()


def clamp(x, lo, hi):
    return min(max(x, lo), hi)


def zigzag(r):
    return 2 * r if r >= 0 else -2 * r - 1


def unzigzag(u):
    return u >> 1 if u % 2 == 0 else -((u + 1) >> 1)


def rdiv(num, den):
    """floor((2*num + den) / (2*den)): num/den rounded half up, the text's usual rounding."""
    return (2 * num + den) // (2 * den)


def read_varint(b, pos):
    """qsp_format.md "Conventions": minimal unsigned LEB128, at most 10 bytes, fits in 64 bits."""
    v = 0
    start = pos
    while True:
        need(pos < len(b), 'varint runs past the end')
        x = b[pos]
        v |= (x & 0x7F) << (7 * (pos - start))
        pos += 1
        if not x & 0x80:
            break
        need(pos - start < 10, 'varint longer than 10 bytes')
    need(pos - start == 1 or b[pos - 1] != 0, 'non-minimal varint')
    need(v < 1 << 64, 'varint above 64 bits')
    return v, pos


# ---------------- qsp_format.md "Entropy coding" ----------------
class Model:
    """A bit model ("Models"): two estimates and a saturating count."""
    __slots__ = ('fast', 'slow', 'seen')

    def __init__(self, p=32768, seen=0):
        self.fast = p
        self.slow = p
        self.seen = seen

    def p0(self):
        return (self.fast + self.slow) >> 1

    def update(self, b):
        w = bit_width(self.seen + 1)
        sf = min(4, w)
        ss = min(7, w)
        if b == 0:
            self.fast += (65536 - self.fast) >> sf
            self.slow += (65536 - self.slow) >> ss
        else:
            self.fast -= self.fast >> sf
            self.slow -= self.slow >> ss
        self.seen = min(self.seen + 1, 255)


class Table(dict):
    """Bit models by index, created on first use; `fresh(key)` makes a new one."""

    def __init__(self, fresh=lambda key: Model()):
        super().__init__()
        self.fresh = fresh

    def __missing__(self, key):
        m = self.fresh(key)
        self[key] = m
        return m


# "Logistic decisions"
SQUASH_T = [1, 2, 3, 6, 10, 16, 27, 45, 73, 120, 194, 310, 488, 747, 1101, 1546, 2047,
            2549, 2994, 3348, 3607, 3785, 3901, 3975, 4024, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094]
MIX_RATE = 6                             # err = 6 * (4096*bit - p1)
MIX_START = (24576, 12288, 12288, 12288, 0)
MIX_BIAS = 256                           # st_4


def _squash(d):
    j = d // 128 + 16
    f = d - 128 * (d // 128)
    return (SQUASH_T[j] * (128 - f) + SQUASH_T[j + 1] * f + 64) >> 7


SQUASH = {d: _squash(d) for d in range(-2047, 2048)}


def _stretch(p):
    for d in range(-2047, 2048):
        if SQUASH[d] >= p:
            return d
    return 2047


STRETCH = [_stretch(p) for p in range(4096)]

# "Length prior": P[c][node]
PRIOR_BELOW, PRIOR_ABOVE = 1, 3          # delta = c - l below, 3*(l - c) above


def _length_prior():
    table = []
    for c in range(24):
        om = [0] * 128
        for l in range(64):
            delta = PRIOR_BELOW * (c - l) if l <= c else PRIOR_ABOVE * (l - c)
            om[64 + l] = 1 << (40 - min(40, delta))
        for node in range(63, 0, -1):
            om[node] = om[2 * node] + om[2 * node + 1]
        table.append([0] + [clamp((om[2 * node] << 16) // om[node], 1024, 64512) for node in range(1, 64)])
    return table


LENGTH_PRIOR = _length_prior()


class Coder:
    """The symbols a stream codes, over decide(p0, bit) and raw(bit) of a range decoder or encoder.
    Every method takes `want`, the bit or value to encode; a decoder ignores it and returns what it
    decodes, an encoder codes it and returns it."""

    def bit(self, m, want=None):
        b = self.decide(m.p0(), want)
        m.update(b)
        return b

    def mixed(self, A, B, want=None):
        """geometry "Mixed decisions"."""
        if A.seen >= 64:
            return self.bit(A, want)
        wA = min(A.seen, 30) + 1
        wB = min(B.seen, 30) + 1
        b = self.decide((A.p0() * wA + B.p0() * wB) // (wA + wB), want)
        A.update(b)
        B.update(b)
        return b

    def logistic(self, models, W, want=None, rate=MIX_RATE):
        """geometry "Logistic decisions": four models and a weight set W (updated in place); `rate`
        the weights' learning rate (6; the coded comments section's text model: 10)."""
        st = [STRETCH[clamp(4096 - (m.p0() >> 4), 1, 4095)] for m in models] + [MIX_BIAS]
        dot = sum(W[k] * st[k] for k in range(5))
        p1 = SQUASH[clamp(dot >> 16, -2047, 2047)]
        b = self.decide(clamp(16 * (4096 - p1), 71, 65465), want)
        err = rate * (4096 * b - p1)
        for k in range(5):
            W[k] = clamp(W[k] + ((st[k] * err) >> 14), -(1 << 22), 1 << 22)
        for m in models:
            m.update(b)
        return b

    def integer(self, t, want=None):
        """An integer model ("Models"), its bit models in table t."""
        nw = None if want is None else bit_width(want + 1) - 1
        n = 0
        while n < 31 and self.bit(t['prefix', n], None if want is None else int(n < nw)) == 1:
            n += 1
        x = 1
        for i in range(n - 1, -1, -1):
            wb = None if want is None else ((want + 1) >> i) & 1
            if n <= 8:
                b = self.bit(t['tree', (1 << n) + x - 1], wb)  # node = x: 1 then 2*node + bit
            else:
                b = self.bit(t['tail', 32 * n + i], wb)
            x = 2 * x + b
        return x - 1


class RangeDecoder(Coder):
    """LZMA's range decoder with 16-bit probabilities and compact ends."""

    def __init__(self, data):
        self.data = data
        self.pos = 0
        self.past = 0          # zeros read past the end
        self.last4 = [0, 0, 0, 0]
        self.range = 0xFFFFFFFF
        self.code = 0
        for _ in range(4):
            self.code = (self.code << 8) | self.byte()
        need(self.code < self.range, 'value outside the coder\'s interval')

    def byte(self):
        if self.pos < len(self.data):
            x = self.data[self.pos]
            self.pos += 1
        else:
            self.past += 1
            need(self.past <= 4, 'ends too early')
            x = 0
        self.last4 = self.last4[1:] + [x]
        return x

    def normalize(self):
        while self.range < 1 << 24:
            self.range = (self.range << 8) & 0xFFFFFFFF
            self.code = ((self.code << 8) | self.byte()) & 0xFFFFFFFF

    def decide(self, p0, want=None):
        assert 1 <= p0 <= 65535
        bound = (self.range >> 16) * p0
        if self.code < bound:
            self.range = bound
            b = 0
        else:
            self.code -= bound
            self.range -= bound
            b = 1
        self.normalize()
        return b

    def raw(self, want=None):
        self.range >>= 1
        b = 1 if self.code >= self.range else 0
        if b:
            self.code -= self.range
        self.normalize()
        need(self.code < self.range, 'value outside the coder\'s interval (raw bit)')
        return b

    def finish(self):
        """"Compact ends": the stream must end exactly where and as the encoder ends it."""
        win = 0
        for x in self.last4:
            win = (win << 8) | x
        lw = (win - self.code) % (1 << 32)
        k, V = compact_end(lw, self.range)
        need(self.pos == len(self.data),
             'does not end where its symbols end (%d bytes unread)' % (len(self.data) - self.pos))
        need(self.past == k and win == V % (1 << 32), 'does not end as the encoder ends it')


def compact_end(low, rng):
    """"Compact ends": the largest k in 4..1 whose multiple V of 2^(8k) at or above low is < low + range."""
    for k in (4, 3, 2, 1):
        unit = 1 << (8 * k)
        V = -(-low // unit) * unit
        if V < low + rng:
            return k, V
    raise AssertionError('range < 2^24')


class RangeEncoder(Coder):
    """The encoder of qsp_format.md "Entropy coding", for recoding a section with other tools."""

    def __init__(self):
        self.low = 0
        self.range = 0xFFFFFFFF
        self.cache = 0
        self.cache_size = 1
        self.out = bytearray()

    def shift_low(self):
        if self.low < 0xFF000000 or self.low >= 1 << 32:
            carry = self.low >> 32
            self.out.append((self.cache + carry) & 0xFF)
            self.out += bytes([(0xFF + carry) & 0xFF]) * (self.cache_size - 1)
            self.cache = (self.low >> 24) & 0xFF
            self.cache_size = 0
        self.cache_size += 1
        self.low = (self.low & 0x00FFFFFF) << 8

    def normalize(self):
        while self.range < 1 << 24:
            self.range <<= 8
            self.shift_low()

    def decide(self, p0, want):
        bound = (self.range >> 16) * p0
        if want == 0:
            self.range = bound
        else:
            self.low += bound
            self.range -= bound
        self.normalize()
        return want

    def raw(self, want):
        self.range >>= 1
        if want:
            self.low += self.range
        self.normalize()
        return want

    def finish(self):
        k, self.low = compact_end(self.low, self.range)
        for _ in range(5):
            self.shift_low()
        assert self.out[0] == 0 and not any(self.out[len(self.out) - k:])
        return bytes(self.out[1:len(self.out) - k])


# ---------------- "Values per axis" ----------------
def image(u):
    return u ^ (0xFFFFFFFF if u >> 31 else 0x80000000)


def unimage(m):
    return m ^ (0x80000000 if m >> 31 else 0xFFFFFFFF)


def f32_bits_of_double(d):
    """d rounded to binary32 (nearest, ties to even), as bits; overflow gives an infinity."""
    try:
        return struct.unpack('<I', struct.pack('<f', d))[0]
    except OverflowError:
        return 0xFF800000 if d < 0 else 0x7F800000


def bits_f32(u):
    return struct.unpack('<f', struct.pack('<I', u))[0]


def f32_of_rational(num, den):
    """The binary32 nearest to num/den (den > 0), ties to even, as bits; num/den is far from overflow."""
    if num == 0:
        return 0
    sign = 0x80000000 if num < 0 else 0
    num = abs(num)
    e = num.bit_length() - den.bit_length() - 24     # want 2^23 <= num / (den*2^e) < 2^24
    while True:
        a, b = (num, den << e) if e >= 0 else (num << -e, den)
        if a < b << 23:
            e -= 1
        elif a >= b << 24:
            e += 1
        else:
            break
    e = max(e, -149)                                  # subnormals: a fixed quantum of 2^-149
    a, b = (num, den << e) if e >= 0 else (num << -e, den)
    q, r = divmod(a, b)
    if 2 * r > b or (2 * r == b and q & 1):
        q += 1
    if q == 1 << 24:
        q >>= 1
        e += 1
    if q < 1 << 23:
        return sign | q
    assert e + 150 < 255
    return sign | ((e + 150) << 23) | (q - (1 << 23))


# ---------------- container (qsp_format.md "File structure", "Sections") ----------------
def sections(b):
    need(b[:8] == bytes([0x89, 0x51, 0x53, 0x50, 0x0D, 0x0A, 0x1A, 0x0A]), 'not a .qsp file')
    need(b[8] == 3, 'major version %d, not 3' % b[8])
    size, pos = read_varint(b, 11)
    need(size == len(b), 'declared size %d, file has %d bytes' % (size, len(b)))
    out = {}
    while pos < size - 8:
        tag = b[pos]
        ln, pos = read_varint(b, pos + 1)
        need(pos + ln <= size - 8, 'section 0x%02x runs into the checksum' % tag)
        need(not out or tag > max(out), 'sections out of order')
        out[tag] = b[pos:pos + ln]
        pos += ln
    return out


def counts(payload):
    pos = 0
    out = []
    for _ in range(4):
        v, pos = read_varint(payload, pos)
        out.append(v)
    return out  # V, F, C, U


def load_stencils(path):
    coding = []
    st = []
    for line in open(path):
        t = [int(x) for x in line.split()]
        assert len(t) == 25, 'stencil line has %d numbers, not 25' % len(t)
        coding.append(t[0])
        d = dict(zip(FIELDS, t[1:20]))
        d['far_dist'], d['e_dist'], d['n_dist'], d['xnum'], d['xden'] = t[20:25]
        st.append(d)
    return coding, st


# ---------------- "Header" ----------------
class Axis:
    """How one axis is stored: kind 'q' (quantized), 'dec' (decimal grid) or 'float' (float bits)."""

    def __init__(self, kind, decimals=0, tz=False, exceptions=None):
        self.kind = kind
        self.decimals = decimals
        self.tz = tz
        self.exceptions = exceptions or {}

    def __repr__(self):
        if self.kind == 'dec':
            return 'dec%d%s%s' % (self.decimals, '+tz' if self.tz else '',
                                  '+%dexc' % len(self.exceptions) if self.exceptions else '')
        return self.kind


def parse_header(sec, V):
    need(len(sec) >= 2, 'section too short for its header')
    tools, bits = sec[0], sec[1]
    pos = 2
    need(tools & 0xC0 == 0, 'reserved tool bit set (tools 0x%02x)' % tools)
    need(bits <= 30, 'bits %d > 30' % bits)
    origin = step = None
    axes = []
    if bits > 0:
        need(len(sec) >= pos + 20, 'section too short for its header')
        origin = struct.unpack_from('<3f', sec, pos)
        pos += 12
        step_bits = struct.unpack_from('<Q', sec, pos)[0]
        step = struct.unpack_from('<d', sec, pos)[0]
        pos += 8
        need(all(math.isfinite(o) for o in origin), 'origin not finite')
        need(math.isfinite(step) and step_bits >> 63 == 0, 'step not finite or negative')
        need(step_bits & ((1 << 30) - 1) == 0, 'step has more than 23 significant bits')
        axes = [Axis('q') for _ in range(3)]
    else:
        for _ in range(3):
            need(pos < len(sec), 'section too short for its header')
            mode = sec[pos]
            pos += 1
            tz = bool(mode & 0x80)
            m = mode & 0x7F
            need(m <= 10, 'axis mode %d' % mode)
            if m == 0:
                need(not tz, 'trailing-zero coding on a float-bits axis')
                axes.append(Axis('float'))
                continue
            count, pos = read_varint(sec, pos)
            need(count <= V and count <= (len(sec) - pos) // 5, 'exception count %d' % count)
            exc = {}
            at = -1
            for _ in range(count):
                gap, pos = read_varint(sec, pos)
                at += 1 + gap
                need(at < V, 'exception at %d >= V' % at)
                need(pos + 4 <= len(sec), 'section too short for its exceptions')
                exc[at] = struct.unpack_from('<I', sec, pos)[0]
                pos += 4
            axes.append(Axis('dec', m - 1, tz, exc))
    need(not tools & MIRROR or all(ax.kind != 'float' for ax in axes), 'mirror prediction on a float-bits axis')
    return tools, bits, origin, step, axes, sec[pos:]


# ---------------- the stencil's neighbourhood ("Neighbourhood") ----------------
def full(sten):
    return sten['w'] != NONE and sten['s'] != NONE and sten['sw'] != NONE


class Hood:
    """The neighbourhood of one vertex: kind, context kind, the fields that count, across class."""
    __slots__ = ('kind', 'ctx', 'fallback', 'nb', 'far', 'D', 'ac', 'e_dist', 'n_dist')


def neighbourhood(i, st, east, layout_order):
    s0 = st[i]
    h = Hood()
    nb = {'w': s0['w'], 's': s0['s']}
    nb['ww'] = s0['ww'] if nb['w'] != NONE else NONE
    nb['sw'] = s0['sw'] if nb['w'] != NONE and nb['s'] != NONE else NONE
    w, s, sw = nb['w'], nb['s'], nb['sw']
    if w != NONE and s != NONE and sw != NONE:
        kind = 3
    elif w != NONE and nb['ww'] != NONE:
        kind = 2
    elif w != NONE:
        kind = 1
    elif s != NONE:
        kind = 4
    else:
        kind = 0
        if i > 0:
            nb['w'] = i - 1  # the previous vertex stands in for w from here on
    h.far = NONE
    h.D = 0
    if kind in (1, 2) and s0['far'] != NONE and 1 <= s0['far_dist'] <= 64:
        h.far, h.D = s0['far'], s0['far_dist']
    h.ctx = kind + 4 if h.far != NONE else kind
    h.fallback = kind
    h.ac = None
    if kind in (1, 2):
        if s0['o'] != NONE and s0['ow'] != NONE:
            kind, h.ctx = 5, 7
            opp_far = s0['far'] != NONE and s0['ofar'] != NONE and 1 <= s0['far_dist'] <= 64
            h.ac = 0 if opp_far else 1
        elif s0['x0'] != NONE and s0['x1'] != NONE and (
                s0['x2'] != NONE or (1 <= s0['xden'] and s0['xnum'] <= s0['xden'])):
            kind, h.ctx = 6, 8
            h.ac = 2 if s0['x2'] != NONE else 3
    h.kind = kind
    h.e_dist = h.n_dist = 0
    if kind == 3:
        if s0['e'] != NONE and s0['es'] != NONE and s0['e_dist'] >= 1:
            nb['e'], nb['es'], h.e_dist = s0['e'], s0['es'], s0['e_dist']
        if s0['n'] != NONE and s0['nw'] != NONE and s0['n_dist'] >= 1:
            nb['n'], nb['nw'], h.n_dist = s0['n'], s0['nw'], s0['n_dist']
        if not layout_order:
            for f in ('se', 'ss', 'sww', 'ssw'):
                nb[f] = s0[f]
        else:
            e = east[i]
            if e != NONE and st[e]['sw'] == s and st[e]['s'] != NONE and st[e]['s'] < i:
                nb['se'] = st[e]['s']
            nb['ss'] = st[s]['s']
            if full(st[s]):
                if st[s]['sw'] != NONE and st[s]['sw'] == st[sw]['s']:
                    nb['ssw'] = st[sw]['s']
                if st[s]['ww'] != NONE and st[s]['ww'] == st[sw]['w']:
                    nb['sww'] = st[sw]['w']
    h.nb = {f: j for f, j in nb.items() if j != NONE}
    return h


# "Candidates": the neighbours each needs
NEEDS = [('w', 's', 'sw'), ('w', 'ww'), ('w', 'ww', 's', 'sw', 'se'), ('s', 'ss'),
         ('w', 'ww', 's', 'sw', 'sww'), ('w', 's', 'sw', 'ss', 'ssw'), ('w',), ('w', 'se', 'sw'),
         ('w', 's', 'sw', 'e', 'es'), ('w', 's', 'sw', 'n', 'nw'), ('w', 's', 'sw', 'e', 'es', 'n', 'nw'),
         ('w', 's', 'sw'), ('w', 'ww', 's', 'sw', 'sww'), ('w', 's', 'sw', 'ss', 'ssw')]
SHRINK_NUM, SHRINK_SHIFT = 13, 4         # candidate 11: 13/16


def transfer(sw, a, b, a1, b1, d1):
    """Tr(a, b, a', b') of "Shape transfers" (a1, b1, d1 are a', b', delta'), or None."""
    lim = 1 << 15
    if any(x <= -lim or x >= lim for vec in (a, b, a1, b1, d1) for x in vec):
        return None
    dot = lambda x, y: x[0] * y[0] + x[1] * y[1] + x[2] * y[2]
    E1, G1, E, G = dot(a1, a1), dot(a1, b1), dot(a, a), dot(a, b)
    Q21 = E1 * dot(b1, b1) - G1 * G1
    Q2 = E * dot(b, b) - G * G
    if Q21 == 0 or Q2 == 0:
        return None
    R = math.isqrt(Q21) * math.isqrt(Q2)
    p = dot(d1, a1)
    q = E1 * dot(d1, b1) - G1 * p
    den = R * E1
    return [sw[j] + rdiv(p * a[j] * R + q * (E * b[j] - G * a[j]), den) for j in range(3)]


def shape_candidate(val, nb, corner, row_end, col_end, fourth):
    """Candidate 12 (west cell) or 13 (south cell) on the three axes, or None if absent."""
    at = lambda f: [val[a][nb[f]] for a in range(3)]
    vec = lambda x, y: [p - q for p, q in zip(at(x), at(y))]
    sw = at('sw')
    rho, gamma = vec('s', 'sw'), vec('w', 'sw')
    rho1, gamma1, delta1 = vec(row_end, corner), vec(col_end, corner), vec(fourth, corner)
    t1 = transfer(sw, rho, gamma, rho1, gamma1, delta1)
    t2 = transfer(sw, gamma, rho, gamma1, rho1, delta1)
    if t1 is None or t2 is None:
        return None
    return [(t1[j] + t2[j] + 1) >> 1 for j in range(3)]


# ---------------- the decoder ----------------
def decode_geometry(sec, V, st, target=None, mirror=None):
    """Decodes a geometry section: float bits per axis per coding position, and a summary.
    mirror: per coding position (mirror source, mirror axis) or None, from the symmetry section
    (qspmirror.py; positions past its length have none), or None for a file without one.
    With target (v[k] per axis, as "Values per axis"), encodes them instead after sec's header (sec
    holds only the header) and returns the section; decimal exceptions are coded as their
    prediction, and every value in S at rank <= 63 as a repeat ("Encoder choices")."""
    tools, bits, origin, step, axes, payload = parse_header(sec, V)
    repeats = bool(tools & REPEATS)
    layout_order = bool(tools & LAYOUT_ORDER)
    shapes = bool(tools & CELL_SHAPES)
    mixing = bool(tools & MIXING)
    is_int = [ax.kind != 'float' for ax in axes]
    any_int = any(is_int)
    chaining = bool(tools & CHAINING) and all(is_int)
    mirroring = bool(tools & MIRROR)
    need(not mirroring or mirror is not None, 'mirror prediction without a symmetry section')
    O = [[0] * 3 for _ in range(3)]       # "Mirror prediction": O[g][a]
    ncand = 14 if shapes else 11
    M_len = [bits if ax.kind == 'q' else 42 if ax.kind == 'dec' else 33 for ax in axes]
    QMOD = 1 << bits
    DLIM = (1 << 40) - 1

    rd = RangeDecoder(payload) if target is None else RangeEncoder()
    # "Model tables": every table fresh at the section's start
    length = Table(lambda key: Model(LENGTH_PRIOR[key[1]][key[2]], 3)) if mixing else Table()
    general, mantissa, zeros, repeat = Table(), Table(), Table(), Table()
    rank = Table()
    by_class, by_previous = Table(), Table()
    mantissa_bucket, mantissa_kind, mantissa_class = Table(), Table(), Table()
    weights = {}

    def weight_set(key):
        if key not in weights:
            weights[key] = list(MIX_START)
        return weights[key]

    east = [NONE] * V
    if layout_order:
        for y in range(V):
            if full(st[y]):
                east[st[y]['w']] = y

    val = [[0] * V for _ in range(3)]     # v[k] per axis: q, n or image(f)
    fbits = [[0] * V for _ in range(3)]   # decoded binary32 bits
    L = [[0] * V for _ in range(3)]       # residual lengths
    U = [[0] * V for _ in range(3)]       # min(u, 2^32 - 1), logistic mixing
    err = [None] * V                      # error records: {k: err} per vertex
    S = [set() for _ in range(3)]         # value repeats
    m_ac = [[0, 0] for _ in range(4)]     # across means
    E_n = E_t = 0                         # chaining energies
    stats = {}

    def stat(key):
        stats[key] = stats.get(key, 0) + 1

    def fval(a, j):
        return bits_f32(fbits[a][j])

    def rounded_image(a, d, wj):
        """Kinds 2, 3 (and 5, 6) on float-bits axes: image(d rounded), or image(f[w]) if not finite."""
        r = f32_bits_of_double(d)
        return image(r) if (r >> 23) & 0xFF != 0xFF else image(fbits[a][wj])

    for i in range(V):
        h = neighbourhood(i, st, east, layout_order)
        nb = h.nb
        kind = h.kind
        stat('kind%d' % kind)
        src = mirror[i] if mirroring and i < len(mirror) else None   # (m, g): a mirrored vertex
        if src is not None:
            stat('mirrored')
            h.ctx = 9
            h.ac = None       # no across means
        w = nb.get('w', NONE)
        s = nb.get('s', NONE)
        sw = nb.get('sw', NONE)

        # "Candidates": mask and values on every integer axis
        mask = []
        shape = {}
        if any_int:
            for k in range(ncand):
                if not all(f in nb for f in NEEDS[k]):
                    continue
                if k in (8, 9, 10) and kind != 3:
                    continue
                if k in (12, 13):
                    if not all(is_int):
                        continue
                    t = (shape_candidate(val, nb, 'sww', 'sw', 'ww', 'w') if k == 12 else
                         shape_candidate(val, nb, 'ssw', 'ss', 'sw', 's'))
                    if t is None:
                        continue
                    shape[k] = t
                    stat('shape%d' % k)
                mask.append(k)

        def candidate(a, k):
            g = lambda f: val[a][nb[f]]
            if k == 0: return g('w') + g('s') - g('sw')
            if k == 1: return 2 * g('w') - g('ww')
            if k == 2: return 2 * g('w') - g('ww') - 2 * g('s') + g('sw') + g('se')
            if k == 3: return 2 * g('s') - g('ss')
            if k == 4: return 2 * g('w') - g('ww') + g('s') - 2 * g('sw') + g('sww')
            if k == 5: return 2 * g('s') - g('ss') + g('w') - 2 * g('sw') + g('ssw')
            if k == 6: return g('w')
            if k == 7: return g('w') + ((g('se') - g('sw')) >> 1)
            if k == 11: return g('sw') + ((SHRINK_NUM * (g('w') + g('s') - 2 * g('sw')) + 8) >> SHRINK_SHIFT)
            if k in (12, 13): return shape[k][a]
            R = C = 0
            if k in (8, 10):
                d = h.e_dist + 1
                R = rdiv((g('e') - g('es')) - (g('w') - g('sw')), d)
            if k in (9, 10):
                d = h.n_dist + 1
                C = rdiv((g('n') - g('nw')) - (g('s') - g('sw')), d)
            return g('w') + g('s') - g('sw') + R + C

        cand = [{k: candidate(a, k) for k in mask} if is_int[a] else None for a in range(3)]

        # "Blend" (kind 3 on integer axes): weights and blend class
        blend_w = {}
        bc = 0
        if kind == 3 and any_int and src is None:
            least = None
            for k in mask:
                tot = cnt = 0
                for f in ('w', 's', 'sw', 'se'):
                    j = nb.get(f, NONE)
                    if j != NONE and err[j] is not None and k in err[j]:
                        tot += err[j][k]
                        cnt += 1
                if cnt == 0:
                    tot, cnt = 1000000, 1
                W = (1 << 15) * cnt // (2 * tot + cnt)
                blend_w[k] = W * W
                x = (4 * tot + 2 * cnt) // cnt
                least = x if least is None else min(least, x)
            bc = bit_width(least)

        def blend(a):
            c = cand[a]
            num = sum(blend_w[k] * clamp(c[k] - c[0], -(1 << 28), 1 << 28) for k in mask)
            den = sum(blend_w[k] for k in mask)
            return c[0] if den == 0 else c[0] + rdiv(num, den)

        def fixed_int(a, kd):
            v = val[a]
            if kd == 2:
                if h.far != NONE:
                    D = h.D
                    return rdiv(-D * (D + 1) * v[nb['ww']] + 2 * D * (D + 2) * v[w] + 2 * v[h.far],
                                (D + 1) * (D + 2))
                return 2 * v[w] - v[nb['ww']]
            if kd == 1:
                if h.far != NONE:
                    D = h.D
                    return (2 * (D * v[w] + v[h.far]) + D + 1) // (2 * (D + 1))
                return v[w]
            if kd == 4:
                return v[s]
            return v[w] if i > 0 else 0  # kind 0

        def fixed_float(a, kd):
            if kd == 3:
                return rounded_image(a, (fval(a, w) + fval(a, s)) - fval(a, sw), w)
            if kd == 2:
                return rounded_image(a, (fval(a, w) + fval(a, w)) - fval(a, nb['ww']), w)
            if kd == 1:
                return image(fbits[a][w])
            if kd == 4:
                return image(fbits[a][s])
            return image(fbits[a][w]) if i > 0 else 0x80000000  # kind 0

        s0 = st[i]

        def across(a):
            """"Across-patch kinds 5 and 6": the across prediction A."""
            if is_int[a]:
                v = val[a]
                if h.ac == 0:
                    D = s0['far_dist']
                    return v[s0['o']] + (2 * (D * (v[w] - v[s0['ow']]) + (v[s0['far']] - v[s0['ofar']])) + D + 1) \
                        // (2 * (D + 1))
                if h.ac == 1:
                    return v[w] + v[s0['o']] - v[s0['ow']]
                if h.ac == 2:
                    return v[s0['x1']] + v[s0['x2']] - v[s0['x0']]
                return v[s0['x0']] + rdiv((v[s0['x1']] - v[s0['x0']]) * s0['xnum'], s0['xden'])
            if kind == 5:
                return rounded_image(a, (fval(a, w) + fval(a, s0['o'])) - fval(a, s0['ow']), w)
            if h.ac == 2:
                return rounded_image(a, (fval(a, s0['x1']) + fval(a, s0['x2'])) - fval(a, s0['x0']), w)
            return image(fbits[a][w])

        # "Normal chaining": m, M, A, B before the axes
        chain = chaining and kind == 3 and src is None
        if chain:
            d1 = [val[a][w] - val[a][sw] for a in range(3)]
            far_row = nb['se'] if 'se' in nb else s
            d2 = [val[a][far_row] - val[a][sw] for a in range(3)]
            m = [d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0]]
            sh = max(0, bit_width(max(abs(x) for x in m)) - 15)
            m = [x >> sh for x in m]
            Mm = sum(x * x for x in m)
            T = E_t // 2 + 1
            N = E_n - T if E_n > T else 0
            sc = max(0, bit_width(max(N, T)) - 15)
            A_ch = N >> sc
            B_ch = (T >> sc) + 1
            r_ch = [0, 0, 0]
            stat('chain_aniso' if A_ch > 0 and Mm > 0 else 'chain_iso')

        use_across = h.ac is not None and m_ac[h.ac][0] <= m_ac[h.ac][1]
        P_across = [None] * 3
        P_along = [None] * 3
        prev = 0
        for a in range(3):
            ax = axes[a]
            # "Contexts"
            if w != NONE and s != NONE:
                c = (L[a][w] + L[a][s] + 1) >> 1
            elif w != NONE:
                c = L[a][w]
            elif s != NONE:
                c = L[a][s]
            else:
                c = 0
            c = min(c, 23)
            nc = c
            if kind == 3 and any_int and src is None:
                if mixing:
                    tot = 2 * (U[a][w] + U[a][s]) + U[a][sw]
                    n = 5
                    if 'se' in nb:
                        tot += U[a][nb['se']]
                        n += 1
                    for b in range(a):
                        tot += 2 * U[b][i]
                        n += 2
                    g = bit_width(2 * tot // n)
                    nc = min(23, g)
                    c = min(23, (3 * g + bc + 2) >> 2)
                else:
                    c = min(23, (c + bc + 1) >> 1)
                    nc = c
            pl = min(23, L[a - 1][i]) if a > 0 else 0
            hw = 1 if h.ctx == 3 else 0  # which weight set

            # "Predictors"
            if src is not None:
                m_src, g_ax = src
                P = (-val[a][m_src] if a == g_ax else val[a][m_src]) + O[g_ax][a]
            elif kind == 3:
                P = blend(a) if is_int[a] else fixed_float(a, 3)
            elif kind in (5, 6):
                P_along[a] = fixed_int(a, h.fallback) if is_int[a] else fixed_float(a, h.fallback)
                P_across[a] = across(a)
                P = P_across[a] if use_across else P_along[a]
            else:
                P = fixed_int(a, kind) if is_int[a] else fixed_float(a, kind)
            P_blend = P
            if chain and a >= 1 and A_ch > 0 and Mm > 0:
                dot = sum(m[k] * r_ch[k] for k in range(a))
                K = sum(m[k] * m[k] for k in range(a))
                P += rdiv(A_ch * m[a] * dot, B_ch * Mm + A_ch * K)
            # "Residuals": the clamped prediction
            if ax.kind == 'q':
                p = clamp(P, 0, QMOD - 1)
            elif ax.kind == 'dec':
                p = clamp(P, -DLIM, DLIM)
            else:
                p = P

            exception = ax.kind == 'dec' and i in ax.exceptions
            want = want_rank = None
            if target is not None:  # encoding: the value, and its rank in S if it repeats one
                want = p if exception else target[a][i]
                ordered = sorted(S[a], key=lambda x: (abs(x - p), x))
                want_rank = ordered.index(want) if want in S[a] and ordered.index(want) <= 63 else None
            is_repeat = 0
            if repeats and S[a] and not exception:
                is_repeat = rd.bit(repeat[h.ctx, prev], None if want is None else int(want_rank is not None))
            if is_repeat:
                k = rd.integer(rank, want_rank)
                need(k <= 63, 'rank %d > 63' % k)
                ordered = sorted(S[a], key=lambda x: (abs(x - p), x))
                need(k < len(ordered), 'rank %d beyond the %d values seen' % (k, len(ordered)))
                value = ordered[k]
                if ax.kind == 'q':
                    r = (value - p) % QMOD
                    u = zigzag(r - QMOD if r >= QMOD >> 1 else r)
                else:
                    u = zigzag(value - p)
                prev = 2
                stat('repeat')
            else:
                want_u = want_t = wb = None
                if want is not None:  # "Residuals", the encoder's side
                    if ax.kind == 'q':
                        r = (want - p) % QMOD
                        r = r - QMOD if r >= QMOD >> 1 else r
                    elif ax.kind == 'dec' and ax.tz:
                        want_t = 0
                        while want_t < 12 and want != 0 and want % 10 ** (want_t + 1) == 0:
                            want_t += 1
                        r = want // 10 ** want_t - rdiv(p, 10 ** want_t)
                    else:
                        r = want - p
                    want_u = zigzag(r)
                # "Residual coding": the length
                node = 1
                hsum = 0
                for b in range(5, -1, -1):
                    if want_u is not None:
                        wb = (bit_width(want_u) >> b) & 1
                    if hsum + (1 << b) > M_len[a]:
                        bit = 0
                    elif mixing:
                        bit = rd.logistic((length[h.ctx, c, node], general[h.ctx, node],
                                           by_class[h.ctx, a, nc, node], by_previous[h.ctx, a, pl, node]),
                                          weight_set(('length', hw, node)), wb)
                    else:
                        bit = rd.mixed(length[h.ctx, c, node], general[h.ctx, node], wb)
                    node = 2 * node + bit
                    hsum += bit << b
                Lr = hsum
                need(Lr <= M_len[a], 'length %d above %d' % (Lr, M_len[a]))
                if Lr <= 1:
                    u = Lr
                else:
                    u = 1
                    node = 1
                    for j in range(Lr - 1):
                        if want_u is not None:
                            wb = (want_u >> (Lr - 2 - j)) & 1
                        if j < 2:
                            if mixing:
                                bit = rd.logistic((mantissa[Lr, node], mantissa_bucket[Lr, c, node],
                                                   mantissa_kind[Lr, h.ctx, node], mantissa_class[Lr, a, nc, node]),
                                                  weight_set(('mantissa', hw, node)), wb)
                            else:
                                bit = rd.bit(mantissa[Lr, node], wb)
                            node = 2 * node + bit
                        else:
                            bit = rd.raw(wb)
                        u = 2 * u + bit
                r = unzigzag(u)
                if ax.kind == 'q':
                    value = (p + r) % QMOD
                elif ax.kind == 'dec' and ax.tz:
                    D = min(15, len(str(abs(p)))) if p != 0 else 0
                    node = 1
                    for b in range(3, -1, -1):
                        node = 2 * node + rd.bit(zeros[D, node], None if want_t is None else (want_t >> b) & 1)
                    t = node - 16
                    need(t <= 12, 't %d > 12' % t)
                    ten = 10 ** t
                    mq = r + rdiv(p, ten)
                    need(abs(mq) <= DLIM // ten, '|m * 10^t| >= 2^40')
                    value = mq * ten
                    stat('tz%d' % t)
                elif ax.kind == 'dec':
                    value = p + r
                    need(abs(value) < 1 << 40, '|n| >= 2^40')
                else:
                    value = p + r
                    need(0 <= value <= U32_MAX, 'float image outside [0, 2^32)')
                prev = 1
            # the value, its coordinate and the records
            assert want is None or value == want
            val[a][i] = value
            L[a][i] = bit_width(u)
            U[a][i] = min(u, U32_MAX)
            if ax.kind == 'q':
                fbits[a][i] = f32_bits_of_double(float(origin[a]) + float(value) * step)
            elif exception:
                fbits[a][i] = ax.exceptions[i]
                stat('exception')
            elif ax.kind == 'dec':
                fbits[a][i] = f32_of_rational(value, 10 ** ax.decimals)
            else:
                fbits[a][i] = unimage(value)
            if repeats and not exception:
                S[a].add(value)
            if chain:
                rr = value - P_blend
                if ax.kind == 'q':
                    rr %= QMOD
                    if rr >= QMOD >> 1:
                        rr -= QMOD
                r_ch[a] = clamp(rr, -(1 << 14), 1 << 14)

        # step 5: across means, chaining energies, mirror offsets, error records
        if src is not None:
            m_src, g_ax = src
            for a in range(3):
                O[g_ax][a] = val[a][i] - (-val[a][m_src] if a == g_ax else val[a][m_src])
        if h.ac is not None:
            for which, PP in ((0, P_across), (1, P_along)):
                e = sum(min(abs(val[a][i] - PP[a]), U32_MAX) for a in range(3) if is_int[a] or not any_int)
                m_ac[h.ac][which] = m_ac[h.ac][which] - m_ac[h.ac][which] // 16 + e
        if chain and Mm > 0:
            dot = sum(m[a] * r_ch[a] for a in range(3))
            tot = sum(x * x for x in r_ch)
            e = min(dot * dot // Mm, tot)
            E_n = E_n - E_n // 16 + e
            E_t = E_t - E_t // 16 + (tot - e)
        if any_int:
            err[i] = {k: min(U32_MAX - 1, sum(min(abs(val[a][i] - cand[a][k]), U32_MAX)
                                              for a in range(3) if is_int[a])) for k in mask}
    if target is not None:
        return sec + rd.finish()
    rd.finish()
    names = [n for bit, n in ((REPEATS, 'repeats'), (LAYOUT_ORDER, 'layout'), (CHAINING, 'chaining'),
                              (CELL_SHAPES, 'shapes'), (MIXING, 'mixing'), (MIRROR, 'mirror')) if tools & bit]
    return fbits, dict(tools='+'.join(names) or 'none', bits=bits, axes=axes, stats=stats, values=val)


# ---------------- --recode: the same values under every tools byte ----------------
M64 = (1 << 64) - 1
XXP1, XXP2, XXP3, XXP4, XXP5 = (0x9E3779B185EBCA87, 0xC2B2AE3D27D4EB4F, 0x165667B19E3779F9,
                                0x85EBCA77C2B2AE63, 0x27D4EB2F165667C5)


def _rotl(x, r):
    return ((x << r) | (x >> (64 - r))) & M64


def _xxround(acc, x):
    return (_rotl((acc + x * XXP2) & M64, 31) * XXP1) & M64


def xxh64(b, seed=0):
    """XXH64 (qsp_format.md "Checksum")."""
    n = len(b)
    p = 0
    u64 = lambda i: int.from_bytes(b[i:i + 8], 'little')
    if n >= 32:
        v = [(seed + XXP1 + XXP2) & M64, (seed + XXP2) & M64, seed, (seed - XXP1) & M64]
        while p + 32 <= n:
            v = [_xxround(v[k], u64(p + 8 * k)) for k in range(4)]
            p += 32
        h = (_rotl(v[0], 1) + _rotl(v[1], 7) + _rotl(v[2], 12) + _rotl(v[3], 18)) & M64
        for x in v:
            h = ((h ^ _xxround(0, x)) * XXP1 + XXP4) & M64
    else:
        h = (seed + XXP5) & M64
    h = (h + n) & M64
    while p + 8 <= n:
        h = (_rotl(h ^ _xxround(0, u64(p)), 27) * XXP1 + XXP4) & M64
        p += 8
    if p + 4 <= n:
        h = (_rotl(h ^ ((int.from_bytes(b[p:p + 4], 'little') * XXP1) & M64), 23) * XXP2 + XXP3) & M64
        p += 4
    while p < n:
        h = (_rotl(h ^ ((b[p] * XXP5) & M64), 11) * XXP1) & M64
        p += 1
    h = ((h ^ (h >> 33)) * XXP2) & M64
    h = ((h ^ (h >> 29)) * XXP3) & M64
    return h ^ (h >> 32)


def varint(v):
    out = bytearray()
    while True:
        x = v & 0x7F
        v >>= 7
        out.append(x | (0x80 if v else 0))
        if not v:
            return bytes(out)


def container(b, secs):
    """File b with its sections replaced by secs: the shortest consistent size field, a new checksum."""
    body = b''.join(bytes([t]) + varint(len(p)) + p for t, p in sorted(secs.items()))
    n = 1
    while len(varint(11 + n + len(body) + 8)) != n:
        n += 1
    out = b[:11] + varint(11 + n + len(body) + 8) + body
    return out + xxh64(out).to_bytes(8, 'little')


def recode(path, outdir, tool_bytes):
    """Writes FILE's mesh again with each tools byte: the same header and values, coded by this
    file's encoder, the coding order from qsplayout.py. Returns the files written. A file with a
    symmetry section keeps it under the tools bytes with bit 5 (mirror prediction) and drops it under
    the others."""
    import os
    import qsplayout
    b = open(path, 'rb').read()
    secs = sections(b)
    V, F, C, U = counts(secs[1])
    geo = secs[3]
    order = {lo: qsplayout.stencils(secs[2], C, U, lo) for lo in (False, True)}
    coding, st = order[bool(geo[0] & LAYOUT_ORDER)]
    mirrors = {lo: file_mirror(b, secs, order[lo][0]) for lo in (False, True)}
    fb, info = decode_geometry(geo, V, st, mirror=mirrors[bool(geo[0] & LAYOUT_ORDER)])
    tools, bits, origin, step, axes, payload = parse_header(geo, V)
    by_vertex = [[0] * V for _ in range(3)]     # v per layout vertex
    for k in range(V):
        for a in range(3):
            by_vertex[a][coding[k]] = info['values'][a][k]
    exc = [{coding[k]: x for k, x in ax.exceptions.items()} for ax in axes]
    out = []
    for t in tool_bytes:
        c2, s2 = order[bool(t & LAYOUT_ORDER)]
        mir = mirrors[bool(t & LAYOUT_ORDER)] if t & MIRROR else None
        if t & MIRROR and (mir is None or any(ax.kind == 'float' for ax in axes)):
            continue    # no symmetry section to predict by, or an axis of float bits
        position = {v: k for k, v in enumerate(c2)}
        hdr = bytes([t, bits])
        if bits:
            hdr += geo[2:22]
        for a, ax in enumerate(axes if not bits else []):
            hdr += bytes([0 if ax.kind == 'float' else (1 + ax.decimals) | (0x80 if ax.tz else 0)])
            if ax.kind == 'dec':
                e = sorted((position[v], x) for v, x in exc[a].items())
                hdr += varint(len(e))
                for j, (k, x) in enumerate(e):
                    hdr += varint(k - (e[j - 1][0] if j else -1) - 1) + struct.pack('<I', x)
        sec = decode_geometry(hdr, V, s2, target=[[by_vertex[a][v] for v in c2] for a in range(3)], mirror=mir)
        again, _ = decode_geometry(sec, V, s2, mirror=mir)
        assert all(again[a][position[coding[k]]] == fb[a][k] for k in range(V) for a in range(3))
        name = os.path.join(outdir, '%s_tools%02d.qsp' % (os.path.basename(path)[:-4], t))
        out_secs = {**secs, 3: sec}
        if not t & MIRROR:
            out_secs.pop(0x0f, None)
        open(name, 'wb').write(container(b, out_secs))
        out.append(name)
    return out


def file_mirror(b, secs, coding):
    """The mirror sources of file b's geometry section in the coding order `coding` (qspmirror.py,
    over the layout's quads from qsppoly.py), or None without a symmetry section."""
    if 0x0f not in secs and not (secs[3][:1] and secs[3][0] & MIRROR):
        return None
    import qsppoly
    import qspmirror
    V, F, C, U = counts(secs[1])
    n, quads = qsppoly.layout(secs[2], C, U)
    need(n == V and len(quads) == F, 'counts disagree with the topology')
    return qspmirror.file_mirror(b, secs, V, quads, coding)


def compare_stencils(mine, dumped):
    """Differences between the coding order and stencils built from the text and dump_stencils'."""
    (c1, s1), (c2, s2) = mine, dumped
    if len(c1) != len(c2):
        return [('vertex count', len(c1), len(c2))]
    out = []
    for k in range(len(c1)):
        if c1[k] != c2[k]:
            out.append((k, 'coding', c1[k], c2[k]))
        out += [(k, f, s1[k][f], s2[k][f]) for f in s2[k] if s1[k][f] != s2[k][f]]
    return out


def main():
    if sys.argv[1:2] == ['--recode']:
        tool_bytes = [int(x) for x in sys.argv[4:]] or range(64 if 0x0f in sections(open(sys.argv[2], 'rb').read())
                                                          else 32)
        for name in recode(sys.argv[2], sys.argv[3], tool_bytes):
            print(name)
        return 0
    args = [x for x in sys.argv[1:] if x != '--dumped-stencils']
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    path, prefix = args
    secs = sections(open(path, 'rb').read())
    V, F, C, U = counts(secs[1])
    dumped = load_stencils(prefix + '.stencil')
    assert len(dumped[1]) == V, (len(dumped[1]), V)
    import qsplayout
    try:
        mine = qsplayout.stencils(secs[2], C, U, bool(secs[3][:1] and secs[3][0] & LAYOUT_ORDER))
    except FormatError as e:
        print('%s: topology refused: %s' % (path, e))
        return 1
    diff = compare_stencils(mine, dumped)
    if diff:
        print('%s: %d stencil fields differ from the reference (k, field, text, reference): %s'
              % (path, len(diff), diff[:8]))
    coding, st = dumped if '--dumped-stencils' in sys.argv else mine
    import qspgeo   # (this file runs as __main__: the modules it imports raise qspgeo's FormatError)
    try:
        mirror = file_mirror(open(path, 'rb').read(), secs, coding)
        fb, info = decode_geometry(secs[3], V, st, mirror=mirror)
    except (FormatError, qspgeo.FormatError) as e:
        print('%s: geometry refused: %s' % (path, e))
        return 1
    ref = struct.unpack('<%dI' % (3 * V), open(prefix + '.pos', 'rb').read())
    bad = []
    for k in range(V):
        for a in range(3):
            if fb[a][k] != ref[3 * coding[k] + a]:
                bad.append((k, coding[k], 'xyz'[a], hex(fb[a][k]), hex(ref[3 * coding[k] + a])))
    info.pop('values')
    print(path, 'V=%d' % V, info, 'mismatches=%d' % len(bad), 'first=%s' % (bad[:1],))
    return 1 if bad or diff else 0


if __name__ == '__main__':
    sys.exit(main())
