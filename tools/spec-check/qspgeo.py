#!/usr/bin/env python3
"""Geometry-section decoder for .qsp (revisions 4 to 6), written from format-spec/qsp_format.md alone.

An independent reviewer wrote it from the text without reading src/geometry.cpp or src/entropy.cpp; the
points where the text was not enough were fixed in the spec (25c17c4). Revision 6 (candidates 11-13 and
the shape transfers, the magnitude and neighbour classes, logistic decisions, the length prior) was
added the same way, from the 2.2 text alone. It checks that the spec still describes what the reference
decoder does: check.sh runs it over the golden files and fresh encodes.

usage: qspgeo.py FILE.qsp PREFIX  decodes FILE's geometry with the stencils in PREFIX.stencil and
       compares with PREFIX.pos (the reference decoder's float bits, canonical order); both files come
       from dump_stencils. Exit 0 if every coordinate matches bit for bit, else 1.
The stencil file gives, per coding position k: coding[k], 19 vertex fields, far_dist, e_dist, n_dist,
xnum, xden.
"""
import math, struct, sys
from fractions import Fraction

NONE = -1
FIELDS = ['w', 'ww', 's', 'sw', 'far', 'e', 'es', 'n', 'nw', 'o', 'ow', 'ofar', 'x0', 'x1', 'x2',
          'se', 'ss', 'sww', 'ssw']


def bit_width(u):
    return u.bit_length()


def zig(s):
    return 2 * s if s >= 0 else -2 * s - 1


def unzig(u):
    return u >> 1 if u % 2 == 0 else -((u + 1) >> 1)


def read_varint(b, pos):
    v = 0
    sh = 0
    start = pos
    while True:
        x = b[pos]
        pos += 1
        v |= (x & 0x7F) << sh
        sh += 7
        if not x & 0x80:
            break
    if pos - start > 1 and b[pos - 1] == 0:
        raise ValueError('non-minimal varint')
    return v, pos


# ---------------- entropy coding ----------------
class Model:
    __slots__ = ('fast', 'slow', 'seen')

    def __init__(self):
        self.fast = 32768
        self.slow = 32768
        self.seen = 0

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


class Models(dict):
    """Bit models by key; `init` (optional) gives a fresh model's (p, seen) for a key, else (32768, 0)."""

    def __init__(self, init=None):
        super().__init__()
        self.init = init

    def __missing__(self, key):
        m = Model()
        if self.init is not None:
            st = self.init(key)
            if st is not None:
                m.fast = m.slow = st[0]
                m.seen = st[1]
        self[key] = m
        return m


# logistic decisions (revision 6)
SQ_T = [1, 2, 3, 6, 10, 16, 27, 45, 73, 120, 194, 310, 488, 747, 1101, 1546, 2047,
        2549, 2994, 3348, 3607, 3785, 3901, 3975, 4024, 4050, 4068, 4079, 4085, 4089, 4092, 4093, 4094]
MIX_LR = 6          # err = MIX_LR * (4096*bit - p1)
MIX_W0 = (24576, 12288, 12288, 12288, 0)


def squash(d):
    j = (d // 128) + 16
    f = d - 128 * (d // 128)
    return (SQ_T[j] * (128 - f) + SQ_T[j + 1] * f + 64) >> 7


SQUASH = [squash(d) for d in range(-2047, 2048)]


def _stretch_table():
    out = [2047] * 4096
    d = -2047
    for p in range(4096):
        while d <= 2047 and SQUASH[d + 2047] < p:
            d += 1
        out[p] = d if d <= 2047 else 2047
    return out


STRETCH = _stretch_table()


PRIOR_UP = 3  # delta = PRIOR_UP * (l - c) above the class


def _length_prior():
    """P[c][node]: the revision-6 length prior ("Length prior")."""
    P = []
    for c in range(24):
        Om = [0] * 128
        for l in range(64):
            delta = c - l if l <= c else PRIOR_UP * (l - c)
            Om[64 + l] = 1 << (40 - min(40, delta))
        for node in range(63, 0, -1):
            Om[node] = Om[2 * node] + Om[2 * node + 1]
        P.append([0] + [max(1024, min(64512, (Om[2 * node] << 16) // Om[node])) for node in range(1, 64)])
    return P


LENGTH_PRIOR = _length_prior()


class Weights(dict):
    def __missing__(self, key):
        w = list(MIX_W0)
        self[key] = w
        return w


class RangeDecoder:
    def __init__(self, data, compact):
        self.data = data
        self.pos = 0
        self.past = 0
        self.compact = compact
        self.range = 0xFFFFFFFF
        self.code = 0
        self.last4 = []
        if not compact:
            if self.byte() != 0:
                raise ValueError('first byte not 0')
        for _ in range(4):
            self.code = (self.code << 8) | self.byte()
        if self.code >= self.range:
            raise ValueError('value outside the coder interval')

    def byte(self):
        if self.pos < len(self.data):
            x = self.data[self.pos]
            self.pos += 1
        else:
            if not self.compact:
                raise ValueError('ends too early')
            self.past += 1
            if self.past > 4:
                raise ValueError('ends too early (5th read)')
            x = 0
        self.last4 = (self.last4 + [x])[-4:]
        return x

    def norm(self):
        while self.range < (1 << 24):
            self.range = (self.range << 8) & 0xFFFFFFFF
            self.code = ((self.code << 8) | self.byte()) & 0xFFFFFFFF

    def decide_p(self, p0):
        bound = (self.range >> 16) * p0
        if self.code < bound:
            self.range = bound
            b = 0
        else:
            self.code -= bound
            self.range -= bound
            b = 1
        self.norm()
        return b

    def bit(self, m):
        b = self.decide_p(m.p0())
        m.update(b)
        return b

    def mixed(self, A, B):
        if A.seen >= 64:
            return self.bit(A)
        wA = min(A.seen, 30) + 1
        wB = min(B.seen, 30) + 1
        p0 = (A.p0() * wA + B.p0() * wB) // (wA + wB)
        b = self.decide_p(p0)
        A.update(b)
        B.update(b)
        return b

    def logistic(self, M, W):
        st = [STRETCH[max(1, min(4095, 4096 - (m.p0() >> 4)))] for m in M] + [256]
        dot = sum(W[k] * st[k] for k in range(5))
        p1 = SQUASH[max(-2047, min(2047, dot >> 16)) + 2047]
        p0 = max(71, min(65465, 16 * (4096 - p1)))
        b = self.decide_p(p0)
        err = MIX_LR * (4096 * b - p1)
        for k in range(5):
            W[k] = max(-(1 << 22), min(1 << 22, W[k] + ((st[k] * err) >> 14)))
        for m in M:
            m.update(b)
        return b

    def raw(self):
        self.range >>= 1
        if self.code >= self.range:
            self.code -= self.range
            b = 1
        else:
            b = 0
        self.norm()
        if self.code >= self.range:
            raise ValueError('value outside the coder interval (raw)')
        return b

    def integer(self, ms, name):
        n = 0
        while n < 31 and self.bit(ms[(name, 'prefix', n)]) == 1:
            n += 1
        x = 1
        if n <= 8:
            node = 1
            for _ in range(n):
                b = self.bit(ms[(name, 'tree', (1 << n) + node - 1)])
                node = 2 * node + b
                x = 2 * x + b
        else:
            for i in range(n - 1, -1, -1):
                b = self.bit(ms[(name, 'tail', 32 * n + i)])
                x = 2 * x + b
        return x - 1

    def finish(self):
        if not self.compact:
            if self.pos != len(self.data) or self.code != 0:
                raise ValueError('LZMA end check failed')
            return
        win = 0
        for x in self.last4:
            win = (win << 8) | x
        lw = (win - self.code) % (1 << 32)
        k = None
        V = None
        for kk in (4, 3, 2, 1):
            unit = 1 << (8 * kk)
            VV = -(-lw // unit) * unit
            if VV < lw + self.range:
                k, V = kk, VV
                break
        if self.pos != len(self.data):
            raise ValueError('does not end where its symbols end (%d bytes unread)' % (len(self.data) - self.pos))
        if self.past != k or win != V % (1 << 32):
            raise ValueError('does not end as the encoder ends it (k=%s past=%d)' % (k, self.past))


# ---------------- values ----------------
def f32_bits(x):
    return struct.unpack('<I', struct.pack('<f', x))[0]


def bits_f32(u):
    return struct.unpack('<f', struct.pack('<I', u))[0]


def image(u):
    return u ^ (0xFFFFFFFF if u >> 31 else 0x80000000)


def unimage(m):
    return m ^ (0x80000000 if m >> 31 else 0xFFFFFFFF)


def rat_to_f32_bits(num, den):
    """binary32 nearest to num/den (den > 0), ties to even; returns bits."""
    if num == 0:
        return 0
    sign = 0
    if num < 0:
        sign = 1
        num = -num
    # find e with 2^23 <= num/den * 2^-e < 2^24
    e = num.bit_length() - den.bit_length() - 24
    while True:
        if e >= 0:
            a, bb = num, den << e
        else:
            a, bb = num << (-e), den
        if a < (bb << 23):
            e -= 1
            continue
        if a >= (bb << 24):
            e += 1
            continue
        break
    if e < -149:  # subnormal
        e = -149
    if e >= 0:
        a, bb = num, den << e
    else:
        a, bb = num << (-e), den
    q, r = divmod(a, bb)
    if 2 * r > bb or (2 * r == bb and q & 1):
        q += 1
    # q is mantissa (with hidden bit) at exponent e
    if q >= (1 << 24):
        q >>= 1
        e += 1
    if q < (1 << 23):  # subnormal
        assert e == -149
        return (sign << 31) | q
    biased = e + 23 + 127
    assert biased < 255
    return (sign << 31) | (biased << 23) | (q - (1 << 23))


def f32_from_double(d):
    return f32_bits(d)  # struct.pack('<f') rounds double to nearest float32 (ties even)


# ---------------- container ----------------
def sections(b):
    assert b[:8] == bytes([0x89, 0x51, 0x53, 0x50, 0x0D, 0x0A, 0x1A, 0x0A])
    major, minor = b[8], b[9]
    size, pos = read_varint(b, 11)
    assert size == len(b)
    out = {}
    while pos < size - 8:
        tag = b[pos]
        ln, pos = read_varint(b, pos + 1)
        out[tag] = b[pos:pos + ln]
        pos += ln
    return (major, minor), out


def counts(payload):
    pos = 0
    V, pos = read_varint(payload, pos)
    F, pos = read_varint(payload, pos)
    C, pos = read_varint(payload, pos)
    U, pos = read_varint(payload, pos)
    return V, F, C, U


# ---------------- geometry ----------------
def load_stencils(path):
    coding = []
    st = []
    for line in open(path):
        t = [int(x) for x in line.split()]
        coding.append(t[0])
        d = dict(zip(FIELDS, t[1:20]))
        d['far_dist'], d['e_dist'], d['n_dist'], d['xnum'], d['xden'] = t[20:25]
        st.append(d)
    return coding, st


def transfer(sw, a, b, a1, b1, d1):
    """T(a, b, a', b') of "Shape transfers" (a1, b1, d1 are a', b', d'), or None if it does not exist."""
    lim = 1 << 15
    for vec in (a, b, a1, b1, d1):
        for x in vec:
            if x <= -lim or x >= lim:
                return None
    dot = lambda x, y: x[0] * y[0] + x[1] * y[1] + x[2] * y[2]
    E1 = dot(a1, a1); G1 = dot(a1, b1); E = dot(a, a); G = dot(a, b)
    Q21 = E1 * dot(b1, b1) - G1 * G1
    Q2 = E * dot(b, b) - G * G
    if E1 == 0 or Q21 == 0 or Q2 == 0:
        return None
    S = math.isqrt(Q21) * math.isqrt(Q2)
    p = dot(d1, a1)
    q = E1 * dot(d1, b1) - G1 * p
    den = S * E1
    out = []
    for k in range(3):
        num = p * a[k] * S + q * (E * b[k] - G * a[k])
        out.append(sw[k] + (2 * num + den) // (2 * den))
    return out


def shape_candidate(val, nb, corner, e1, f1, d1):
    """Candidate 12 (west cell: corner sww) or 13 (south cell: corner ssw), per axis; None if absent."""
    vec = lambda x, y: [val[k][nb[x]] - val[k][nb[y]] for k in range(3)]
    sw = [val[k][nb['sw']] for k in range(3)]
    e = vec('s', 'sw'); f = vec('w', 'sw')
    e_ = vec(e1, corner); f_ = vec(f1, corner); d_ = vec(d1, corner)
    t = transfer(sw, e, f, e_, f_, d_)
    u = transfer(sw, f, e, f_, e_, d_)
    if t is None or u is None:
        return None
    return [(t[k] + u[k] + 1) // 2 for k in range(3)]


def decode_geometry(sec, V, st, verbose=False):
    pos = 0
    rev = sec[pos]; pos += 1
    assert rev in (4, 5, 6), rev
    bits = sec[pos]; pos += 1
    flags = sec[pos]; pos += 1
    assert flags & ~(7 if rev == 6 else 3) == 0
    repeats = bool(flags & 1)
    layout_order = bool(flags & 2)
    r6 = rev == 6
    axes = []  # per axis: ('q',) | ('dec', k, tz, exceptions dict) | ('float',)
    if bits > 0:
        origin = struct.unpack_from('<3f', sec, pos); pos += 12
        step = struct.unpack_from('<d', sec, pos)[0]; pos += 8
        for a in range(3):
            axes.append(('q',))
    else:
        origin = step = None
        for a in range(3):
            mode = sec[pos]; pos += 1
            tz = bool(mode & 0x80)
            md = mode & 0x7F
            if md == 0:
                assert not tz
                axes.append(('float',))
            else:
                assert 1 <= md <= 10
                cnt, pos = read_varint(sec, pos)
                exc = {}
                idx = -1
                for e in range(cnt):
                    gap, pos = read_varint(sec, pos)
                    idx = idx + 1 + gap
                    exc[idx] = struct.unpack_from('<I', sec, pos)[0]; pos += 4
                axes.append(('dec', md - 1, tz, exc))
    psize, pos = read_varint(sec, pos)
    payload = sec[pos:]
    assert len(payload) == psize
    rd = RangeDecoder(payload, compact=True)

    def prior(key):  # revision 6: length[ctx][c][node] starts at the length prior
        if r6 and key[0] == 'length':
            return LENGTH_PRIOR[key[2]][key[3]], 3
        return None
    ms = Models(prior)
    mix = Weights()  # revision 6 weight sets

    is_int = [ax[0] != 'float' for ax in axes]
    any_int = any(is_int)
    all_int = all(is_int)
    chaining = (rev == 5 or (r6 and flags & 4)) and all_int
    ncand = 14 if r6 else 11
    maxlen = []
    for ax in axes:
        maxlen.append(bits if ax[0] == 'q' else 42 if ax[0] == 'dec' else 33)

    # neighbourhood (layout order needs east)
    def full(y):
        s = st[y]
        return s['w'] != NONE and s['s'] != NONE and s['sw'] != NONE
    east = [NONE] * V
    if layout_order:
        for y in range(V):
            if full(y):
                east[st[y]['w']] = y

    val = [[0] * V for _ in range(3)]    # v[i] per axis (q, n, or image)
    fbits = [[0] * V for _ in range(3)]  # decoded float bits
    Lw = [[0] * V for _ in range(3)]
    Uw = [[0] * V for _ in range(3)]  # revision 6: min(u, 2^32 - 1)
    err = [None] * V
    S = [set() for _ in range(3)]
    Slist = [[] for _ in range(3)]
    m_ac = [[0, 0] for _ in range(4)]
    E_n = 0
    E_t = 0
    CLAMP_Q = (1 << bits) - 1 if bits else None
    LIM = (1 << 40) - 1

    STATS = {}
    def stat(k):
        STATS[k] = STATS.get(k, 0) + 1
    for i in range(V):
        s0 = st[i]
        w = s0['w']; ww = s0['ww']; s = s0['s']; sw = s0['sw']
        if w == NONE:
            ww = NONE
        if w == NONE or s == NONE:
            sw = NONE
        nb = dict(w=w, ww=ww, s=s, sw=sw)
        isfull = w != NONE and s != NONE and sw != NONE
        if isfull:
            kind = 3
        elif w != NONE and ww != NONE:
            kind = 2
        elif w != NONE:
            kind = 1
        elif s != NONE:
            kind = 4
        else:
            kind = 0
        kind0_w = False
        if kind == 0 and i > 0:
            w = i - 1
            nb['w'] = w
            kind0_w = True
        far = NONE; D = 0
        if kind in (1, 2) and s0['far'] != NONE and 1 <= s0['far_dist'] <= 64:
            far = s0['far']; D = s0['far_dist']
        ctxk = kind + 4 if (kind in (1, 2) and far != NONE) else kind
        fallback = kind
        ac = None
        if kind in (1, 2):
            if s0['o'] != NONE and s0['ow'] != NONE:
                kind = 5
                ctxk = 7
                opp_far = s0['far'] != NONE and s0['ofar'] != NONE and 1 <= s0['far_dist'] <= 64
                ac = 0 if opp_far else 1
            elif s0['x0'] != NONE and s0['x1'] != NONE and (
                    s0['x2'] != NONE or (1 <= s0['xden'] and s0['xnum'] <= s0['xden'])):
                kind = 6
                ctxk = 8
                ac = 2 if s0['x2'] != NONE else 3
        if kind == 3:
            if s0['e'] != NONE and s0['es'] != NONE and s0['e_dist'] >= 1:
                nb['e'] = s0['e']; nb['es'] = s0['es']; e_d = s0['e_dist']
            if s0['n'] != NONE and s0['nw'] != NONE and s0['n_dist'] >= 1:
                nb['n'] = s0['n']; nb['nw'] = s0['nw']; n_d = s0['n_dist']
            if not layout_order:
                for f in ('se', 'ss', 'sww', 'ssw'):
                    if s0[f] != NONE:
                        nb[f] = s0[f]
            else:
                e = east[i]
                if e != NONE and st[e]['sw'] == s and st[e]['s'] != NONE and st[e]['s'] < i:
                    nb['se'] = st[e]['s']
                if st[s]['s'] != NONE:
                    nb['ss'] = st[s]['s']
                if full(s):
                    if st[sw]['s'] != NONE and st[s]['sw'] == st[sw]['s']:
                        nb['ssw'] = st[sw]['s']
                    if st[s]['ww'] != NONE and st[s]['ww'] == st[sw]['w']:
                        nb['sww'] = st[sw]['w']
        stat('kind%d' % kind)
        if kind0_w: stat('kind0w')
        if chaining and kind == 3: stat('chainA>0' if (E_n > E_t // 2 + 1) else 'chainA0')
        nbw = dict(nb)
        # mask
        needs = [('w', 's', 'sw'), ('w', 'ww'), ('w', 'ww', 's', 'sw', 'se'), ('s', 'ss'),
                 ('w', 'ww', 's', 'sw', 'sww'), ('w', 's', 'sw', 'ss', 'ssw'), ('w',), ('w', 'se', 'sw'),
                 ('w', 's', 'sw', 'e', 'es'), ('w', 's', 'sw', 'n', 'nw'),
                 ('w', 's', 'sw', 'e', 'es', 'n', 'nw'),
                 ('w', 's', 'sw'), ('w', 'ww', 's', 'sw', 'sww'), ('w', 's', 'sw', 'ss', 'ssw')]
        mask = [k for k in range(ncand) if all(nbw.get(f, NONE) != NONE for f in needs[k])] if any_int else []
        shape = {}  # revision 6: candidates 12 and 13, per axis
        if r6:
            for k, (corner, e1, f1, d1) in ((12, ('sww', 'sw', 'ww', 'w')), (13, ('ssw', 'ss', 'sw', 's'))):
                if k not in mask:
                    continue
                tr = shape_candidate(val, nb, corner, e1, f1, d1) if all_int else None
                if tr is None:
                    mask.remove(k)
                else:
                    shape[k] = tr
                    stat('shape%d' % k)

        def cand(a, k):
            v = val[a]
            g = lambda f: v[nb[f]]
            if k == 0: return g('w') + g('s') - g('sw')
            if k == 1: return 2 * g('w') - g('ww')
            if k == 2: return 2 * g('w') - g('ww') - 2 * g('s') + g('sw') + g('se')
            if k == 3: return 2 * g('s') - g('ss')
            if k == 4: return 2 * g('w') - g('ww') + g('s') - 2 * g('sw') + g('sww')
            if k == 5: return 2 * g('s') - g('ss') + g('w') - 2 * g('sw') + g('ssw')
            if k == 6: return g('w')
            if k == 7: return g('w') + ((g('se') - g('sw')) >> 1)
            if k == 11: return g('sw') + ((13 * (g('w') + g('s') - 2 * g('sw')) + 8) >> 4)
            if k in (12, 13): return shape[k][a]
            R = C = 0
            if k in (8, 10):
                d = e_d + 1
                R = (2 * ((g('e') - g('es')) - (g('w') - g('sw'))) + d) // (2 * d)
            if k in (9, 10):
                d = n_d + 1
                C = (2 * ((g('n') - g('nw')) - (g('s') - g('sw'))) + d) // (2 * d)
            return g('w') + g('s') - g('sw') + R + C

        cands = [{k: cand(a, k) for k in mask} if is_int[a] else None for a in range(3)]

        # blend
        weights = None
        cls = 0
        if kind == 3 and any_int:
            weights = {}
            mins = None
            for k in mask:
                sm = 0; cnt = 0
                for f in ('w', 's', 'sw', 'se'):
                    j = nb.get(f, NONE)
                    if j != NONE and err[j] is not None and k in err[j]:
                        sm += err[j][k]; cnt += 1
                if cnt == 0:
                    sm = 1000000; cnt = 1
                W = (1 << 15) * cnt // (2 * sm + cnt)
                weights[k] = W * W
                t = (4 * sm + 2 * cnt) // cnt
                mins = t if mins is None else min(mins, t)
            cls = bit_width(mins)

        def blend(a):
            c = cands[a]
            P0 = c[0]
            num = 0; den = 0
            for k in mask:
                dk = max(-(1 << 28), min(1 << 28, c[k] - P0))
                num += weights[k] * dk
                den += weights[k]
            if den == 0:
                return P0
            return P0 + (2 * num + den) // (2 * den)

        def fixed_int(a, kd):
            v = val[a]
            if kd == 2:
                if far != NONE:
                    num = -D * (D + 1) * v[ww] + 2 * D * (D + 2) * v[w] + 2 * v[far]
                    den = (D + 1) * (D + 2)
                    return (2 * num + den) // (2 * den)
                return 2 * v[w] - v[ww]
            if kd == 1:
                if far != NONE:
                    return (2 * (D * v[w] + v[far]) + D + 1) // (2 * (D + 1))
                return v[w]
            if kd == 4:
                return v[s]
            if kd == 0:
                return v[w] if i > 0 else 0
            raise AssertionError

        def fval(a, j):
            return struct.unpack('<f', struct.pack('<I', fbits[a][j]))[0]

        def round_img(a, d, wj):
            try:
                r = struct.pack('<f', d)
                rb = struct.unpack('<I', r)[0]
            except OverflowError:
                return image(fbits[a][wj])
            if (rb >> 23) & 0xFF == 0xFF:
                return image(fbits[a][wj])
            return image(rb)

        def fixed_float(a, kd):
            if kd == 3:
                return round_img(a, (fval(a, w) + fval(a, s)) - fval(a, sw), w)
            if kd == 2:
                return round_img(a, (fval(a, w) + fval(a, w)) - fval(a, ww), w)
            if kd == 1:
                return image(fbits[a][w])
            if kd == 4:
                return image(fbits[a][s])
            if kd == 0:
                return image(fbits[a][w]) if i > 0 else 0x80000000

        def across(a):
            if is_int[a]:
                v = val[a]
                if kind == 5:
                    o, ow = s0['o'], s0['ow']
                    if ac == 0:
                        Dd = s0['far_dist']
                        return v[o] + (2 * (Dd * (v[w] - v[ow]) + (v[s0['far']] - v[s0['ofar']])) + Dd + 1) // (2 * (Dd + 1))
                    return v[w] + v[o] - v[ow]
                x0, x1, x2 = s0['x0'], s0['x1'], s0['x2']
                if ac == 2:
                    return v[x1] + v[x2] - v[x0]
                return v[x0] + (2 * (v[x1] - v[x0]) * s0['xnum'] + s0['xden']) // (2 * s0['xden'])
            if kind == 5:
                return round_img(a, (fval(a, w) + fval(a, s0['o'])) - fval(a, s0['ow']), w)
            if ac == 2:
                return round_img(a, (fval(a, s0['x1']) + fval(a, s0['x2'])) - fval(a, s0['x0']), w)
            return image(fbits[a][w])

        # chaining setup
        chain = chaining and kind == 3
        if chain:
            d1 = [val[a][w] - val[a][sw] for a in range(3)]
            d2 = [val[a][s] - val[a][sw] for a in range(3)]
            if r6 and nb.get('se', NONE) != NONE:  # a row step centred on the vertex's column
                d2 = [val[a][nb['se']] - val[a][sw] for a in range(3)]
            m = [d1[1] * d2[2] - d1[2] * d2[1], d1[2] * d2[0] - d1[0] * d2[2], d1[0] * d2[1] - d1[1] * d2[0]]
            g = bit_width(max(abs(x) for x in m))
            sh = max(0, g - 15)
            m = [x >> sh for x in m]
            M = sum(x * x for x in m)
            T = E_t // 2 + 1
            N = E_n - T if E_n > T else 0
            sc = max(0, bit_width(max(N, T)) - 15)
            Ach = N >> sc
            Bch = (T >> sc) + 1
            rch = [0, 0, 0]

        # magnitude class base
        prev = 0
        Pacr = [None] * 3
        Palg = [None] * 3
        use_across = None
        if ac is not None:
            use_across = m_ac[ac][0] <= m_ac[ac][1]
        Praw = [None] * 3
        for a in range(3):
            ax = axes[a]
            # prediction
            if kind == 3:
                P = blend(a) if is_int[a] else fixed_float(a, 3)
            elif kind in (5, 6):
                F = fixed_int(a, fallback) if is_int[a] else fixed_float(a, fallback)
                A_ = across(a)
                Pacr[a] = A_; Palg[a] = F
                P = A_ if use_across else F
            else:
                P = fixed_int(a, kind) if is_int[a] else fixed_float(a, kind)
            Praw[a] = P
            if chain and a >= 1 and Ach > 0 and M > 0:
                dot = sum(m[k] * rch[k] for k in range(a))
                K = sum(m[k] * m[k] for k in range(a))
                den = Bch * M + Ach * K
                P = P + (2 * Ach * m[a] * dot + den) // (2 * den)
            # clamp
            if ax[0] == 'q':
                p = max(0, min(CLAMP_Q, P))
            elif ax[0] == 'dec':
                p = max(-LIM, min(LIM, P))
            else:
                p = P
            # context
            Lc = Lw[a]
            if w != NONE and s != NONE:
                c = (Lc[w] + Lc[s] + 1) >> 1
            elif w != NONE:
                c = Lc[w]
            elif s != NONE:
                c = Lc[s]
            else:
                c = 0
            c = min(c, 23)
            nc = c
            if kind == 3 and any_int:
                if r6:
                    sm = 2 * (Uw[a][w] + Uw[a][s]) + Uw[a][sw]
                    n_ = 5
                    if nb.get('se', NONE) != NONE:
                        sm += Uw[a][nb['se']]
                        n_ += 1
                    for b_ in range(a):
                        sm += 2 * Uw[b_][i]
                        n_ += 2
                    g_ = bit_width(2 * sm // n_)
                    nc = min(23, g_)
                    c = min(23, (3 * g_ + cls + 2) >> 2)
                else:
                    c = min(23, (c + cls + 1) >> 1)
                    nc = c
            pl = min(23, Lw[a - 1][i]) if a > 0 else 0
            kw = 1 if ctxk == 3 else 0
            is_exc = ax[0] == 'dec' and i in ax[3]
            rep = 0
            if repeats and not is_exc and Slist[a]:
                rep = rd.bit(ms[('repeat', ctxk, prev)])
            if is_exc: stat('exception')
            if ax[0]=='dec' and ax[2]: stat('tz')
            if rep:
                stat('repeat')
                k = rd.integer(ms, 'rank')
                if k > 63:
                    raise ValueError('rank > 63')
                order = sorted(Slist[a], key=lambda x: (abs(x - p), x))
                if k >= len(order):
                    raise ValueError('rank beyond S')
                value = order[k]
                if ax[0] == 'q':
                    r = (value - p) % (1 << bits)
                    if r >= (1 << (bits - 1)):
                        r -= 1 << bits
                    uval = zig(r)
                else:  # decimal (t ignored) and float bits
                    uval = zig(value - p)
                Lval = bit_width(uval)
                prev = 2
            else:
                # length
                node = 1
                h = 0
                for bpos in range(5, -1, -1):
                    wt = 1 << bpos
                    if h + wt > maxlen[a]:
                        b = 0
                    elif r6:
                        b = rd.logistic((ms[('length', ctxk, c, node)], ms[('general', ctxk, node)],
                                         ms[('by_class', ctxk, a, nc, node)], ms[('by_previous', ctxk, a, pl, node)]),
                                        mix[('length', kw, node)])
                    else:
                        b = rd.mixed(ms[('length', ctxk, c, node)], ms[('general', ctxk, node)])
                    node = 2 * node + b
                    h += wt * b
                L = h
                if L > maxlen[a]:
                    raise ValueError('length too large')
                if L >= 2:
                    u = 1
                    node = 1
                    for j in range(L - 1):
                        if j < 2 and r6:
                            b = rd.logistic((ms[('mantissa', L, node)], ms[('mantissa_bucket', L, c, node)],
                                             ms[('mantissa_kind', L, ctxk, node)], ms[('mantissa_class', L, a, nc, node)]),
                                            mix[('mantissa', kw, node)])
                            node = 2 * node + b
                        elif j < 2:
                            b = rd.bit(ms[('mantissa', L, node)])
                            node = 2 * node + b
                        else:
                            b = rd.raw()
                        u = 2 * u + b
                else:
                    u = L
                r = unzig(u)
                Lval = L
                uval = u
                if ax[0] == 'q':
                    value = (p + r) % (1 << bits)
                elif ax[0] == 'dec':
                    if ax[2]:
                        D_ = min(15, len(str(abs(p)))) if p != 0 else 0
                        node = 1
                        t = 0
                        for j in range(4):
                            b = rd.bit(ms[('zeros', D_, node)])
                            node = 2 * node + b
                            t = 2 * t + b
                        if t > 12:
                            raise ValueError('t > 12')
                        pt = 10 ** t
                        mm = r + (2 * p + pt) // (2 * pt)
                        if abs(mm) > ((1 << 40) - 1) // pt:
                            raise ValueError('|m| too large')
                        value = mm * pt
                    else:
                        value = p + r
                        if abs(value) >= (1 << 40):
                            raise ValueError('|n| >= 2^40')
                else:
                    value = p + r
                    if not 0 <= value < (1 << 32):
                        raise ValueError('float image out of range')
                prev = 1  # a decimal exception counts as coded by its residual
            Lw[a][i] = Lval
            Uw[a][i] = min(uval, (1 << 32) - 1)
            val[a][i] = value
            if ax[0] == 'q':
                fbits[a][i] = f32_from_double(float(origin[a]) + float(value) * step)
            elif ax[0] == 'dec':
                if is_exc:
                    fbits[a][i] = ax[3][i]
                else:
                    fbits[a][i] = rat_to_f32_bits(value, 10 ** ax[1])
            else:
                fbits[a][i] = unimage(value)
            if not is_exc and value not in S[a]:  # exceptions never join S
                S[a].add(value)
                Slist[a].append(value)
            if chain:
                rr = value - Praw[a]
                if ax[0] == 'q':
                    rr %= (1 << bits)
                    if rr >= (1 << (bits - 1)):
                        rr -= 1 << bits
                rch[a] = max(-(1 << 14), min(1 << 14, rr))
        # after the vertex
        if any_int:
            e = {}
            for k in mask:
                tot = 0
                for a in range(3):
                    if is_int[a]:
                        tot += min(abs(val[a][i] - cands[a][k]), (1 << 32) - 1)
                e[k] = min((1 << 32) - 2, tot)
            err[i] = e
        if ac is not None:
            for pidx, PP in ((0, Pacr), (1, Palg)):
                ep = 0
                for a in range(3):
                    if is_int[a] or not any_int:
                        ep += min(abs(val[a][i] - PP[a]), (1 << 32) - 1)
                m_ac[ac][pidx] = m_ac[ac][pidx] - m_ac[ac][pidx] // 16 + ep
        if chain and M > 0:
            dot = sum(m[a] * rch[a] for a in range(3))
            tot = sum(x * x for x in rch)
            ee = min(dot * dot // M, tot)
            dec = 16 if r6 else 32
            E_n = E_n - E_n // dec + ee
            E_t = E_t - E_t // dec + (tot - ee)
    rd.finish()
    return fbits, dict(stats=STATS, rev=rev, bits=bits, flags=flags, axes=[a[:3] for a in axes])


def main():
    path, pre = sys.argv[1], sys.argv[2]
    b = open(path, 'rb').read()
    ver, secs = sections(b)
    V, F, C, U = counts(secs[1])
    coding, st = load_stencils(pre + '.stencil')
    assert len(st) == V, (len(st), V)
    fb, info = decode_geometry(secs[3], V, st)
    ref = open(pre + '.pos', 'rb').read()
    refb = struct.unpack('<%dI' % (3 * V), ref)
    bad = 0
    first = None
    for k in range(V):
        g = coding[k]
        for a in range(3):
            if fb[a][k] != refb[3 * g + a]:
                bad += 1
                if first is None:
                    first = (k, g, a, hex(fb[a][k]), hex(refb[3 * g + a]))
    print(path, 'V=%d' % V, info, 'mismatches=%d' % bad, 'first=%s' % (first,))
    return 1 if bad else 0




def main_geo():
    """qspgeo.py --geo PREFIX : decode PREFIX.geo with PREFIX.stencil, compare with PREFIX.pos"""
    pre = sys.argv[2]
    coding, st = load_stencils(pre + '.stencil')
    V = len(st)
    fb, info = decode_geometry(open(pre + '.geo', 'rb').read(), V, st)
    refb = struct.unpack('<%dI' % (3 * V), open(pre + '.pos', 'rb').read())
    bad = sum(1 for k in range(V) for a in range(3) if fb[a][k] != refb[3 * coding[k] + a])
    print(pre, 'V=%d' % V, info, 'mismatches=%d' % bad)
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main_geo() if sys.argv[1] == '--geo' else main())
