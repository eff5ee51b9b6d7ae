#!/usr/bin/env python3
"""The colours section (0x0b, format 3.8) of a .qsp file, written from format-spec/qsp_format.md
("Colours section", and the *Integers* and residual coding of "Texture coordinates section" it
refers to) alone, without reading the codec's C++: each output vertex's and each output face's
colour, binary32 components.

decode_colors() is what qsppoly.py calls; encode_colors() is an encoder of the section that makes the
choices the text says the reference encoder makes (lossless: per component the decimal grid of the
fewest decimals that holds all its values, else float bits; --quantize-color BITS: the binary grid of
step 2^-BITS unless a value is 2^(40 - BITS) or more in magnitude), so that a file's section can be
checked byte for byte against it.

Points where the text leaves a choice are named by the constants below the imports.
"""
import math

import qspgeo as g

FormatError = g.FormatError
need = g.need

LIM = (1 << 40) - 1          # a grid integer q has |q| < 2^40
ESCAPE = (1 << 32) - 2       # min(z, 2^32 - 2) through the integer model, then 21 + 21 raw bits
MAX_NEIGHBOURS = 8
FLOAT_ZERO = 0x80000000      # the image of +0.0: the no-prediction value in float bits

# The text's "the neighbours' integers" and "the neighbour's integer": the integers as decoded (the q
# coded), not, as in the texture coordinates section, the integer a decoded binary32 maps back to (they
# differ only for q no encoder writes: a decimal q whose binary32 is nearer another q)
INTEGER_OF_DECODED = False
# (the encoder: "-0 becomes 0" is said of --quantize-color only; lossless, a -0 component is held
# exactly by no grid, every grid integer 0 giving +0, so its component takes float bits)

STATS = {}


def seen(what):
    STATS[what] = STATS.get(what, 0) + 1


def round_half_away(z):
    """round(z) of a binary64 z, halves away from zero."""
    f = math.floor(z)
    return f + 1 if z - f > 0.5 or (z - f == 0.5 and z > 0) else f


def mode_ok(mode):
    return mode <= 10 or 17 <= mode <= 40


def mode_name(mode):
    return 'float' if mode == 0 else 'dec%d' % (mode - 1) if mode <= 10 else 'bin%d' % (mode - 16)


def den_of(mode):
    return 1 << (mode - 16) if mode >= 17 else 10 ** (mode - 1)


def integer_of(u, mode):
    """The integer of binary32 bits u in `mode` ("Integers"): the image in float bits; else
    round(y * 2^b) (exact) or round(y * 10^k) (one binary64 multiplication), halves away from 0."""
    if mode == 0:
        return g.image(u)
    y = g.bits_f32(u)
    if mode >= 17:
        z = y * float(1 << (mode - 16))
    else:
        z = y * float(10 ** (mode - 1))
    r = round_half_away(z)
    if r - z in (0.5, -0.5):
        seen('colors: integer of a value halfway')
    return r


def value_of(q, mode):
    """The binary32 bits an integer q gives in `mode` (None: a format error, with the reason)."""
    if mode == 0:
        if not 0 <= q < 1 << 32:
            return None, 'colour image %d outside [0, 2^32)' % q
        u = g.unimage(q)
        if u & 0x7F800000 == 0x7F800000:
            return None, 'colour value 0x%08x is not finite' % u
        return u, None
    if not -LIM <= q <= LIM:
        return None, 'colour integer %d outside (-2^40, 2^40)' % q
    return g.f32_of_rational(q, den_of(mode)), None


def corner_vertices(V, faces):
    """Per vertex, the decoded neighbours' candidates: for each of its corners in corner order, the
    vertex of the next corner of that corner's face."""
    nexts = [[] for _ in range(V)]
    for f in faces:
        d = len(f)
        for p, v in enumerate(f):
            nexts[v].append(f[(p + 1) % d])
    return nexts


def neighbours(v, nexts):
    """The decoded neighbours of v: the first 8 of the next vertices below v (repeats count)."""
    out = []
    for u in nexts[v]:
        if u < v:
            out.append(u)
            if len(out) == MAX_NEIGHBOURS:
                break
    return out


def vertex_prediction(v, nb, ints, j, mode):
    """(prediction, model key) of component j of vertex v, from the integers ints[u][j] of decoded
    vertices."""
    n = len(nb)
    if n:
        S = sum(ints[u][j] for u in nb)
        p = (2 * S + n) // (2 * n)
    elif v >= 1:
        p = ints[v - 1][j]
    else:
        p = FLOAT_ZERO if mode == 0 else 0
    return p, 3 * j + min(n, 2)


def face_prediction(gi, nb, ints, j, mode):
    if nb is not None:
        return ints[nb][j], 2 * j
    if gi >= 1:
        return ints[gi - 1][j], 2 * j + 1
    return (FLOAT_ZERO if mode == 0 else 0), 2 * j + 1


class Models:
    def __init__(self):
        self.tables = {}

    def __call__(self, name):
        if name not in self.tables:
            self.tables[name] = g.Table()
        return self.tables[name]


def code_residual(coder, table, r=None):
    """A residual ("Texture coordinates section": zigzag, min(z, 2^32 - 2) through an integer model,
    then w = z - (2^32 - 2) as 21 raw bits of w >> 21 and 21 of w mod 2^21). With r, encodes it."""
    if r is None:
        z = coder.integer(table)
        if z == ESCAPE:
            seen('colors: escape')
            hi = lo = 0
            for _ in range(21):
                hi = 2 * hi + coder.raw()
            for _ in range(21):
                lo = 2 * lo + coder.raw()
            z += (hi << 21) | lo
        return g.unzigzag(z)
    z = g.zigzag(r)
    coder.integer(table, min(z, ESCAPE))
    if z >= ESCAPE:
        w = z - ESCAPE
        assert w < 1 << 42, 'a residual too large for the escape'
        for i in range(41, -1, -1):
            coder.raw((w >> i) & 1)
    return r


def parse_header(payload, V, F):
    """(Kv, Kf, modes, stream) of a section, every rule of its header checked."""
    need(len(payload) >= 1, 'empty colours section')
    flags = payload[0]
    Kv, Kf = flags & 7, (flags >> 3) & 7
    need(flags >> 6 == 0, 'colours: reserved flag bits 6-7 set (flags 0x%02x)' % flags)
    need(Kv in (0, 3, 4), 'colours: vertex components Kv = %d (not 0, 3 or 4)' % Kv)
    need(Kf in (0, 1, 3, 4), 'colours: face components Kf = %d (not 0, 1, 3 or 4)' % Kf)
    need(Kv or Kf, 'colours: Kv = Kf = 0')
    need(len(payload) >= 1 + Kv + Kf, 'colours: the section ends in its modes')
    modes = list(payload[1:1 + Kv + Kf])
    for i, mode in enumerate(modes):
        need(mode_ok(mode), 'colours: component %d mode %d' % (i, mode))
    stream = payload[1 + Kv + Kf:]
    need(V * Kv + F * Kf <= 8192 * (len(stream) + 8),
         'colours: %d components in a stream of %d bytes (at most 8192 * (bytes + 8))' % (V * Kv + F * Kf, len(stream)))
    return Kv, Kf, modes, stream


def decode_colors(payload, V, F, faces, minor=8):
    """The section over the output mesh before an order section (V vertices, the F faces `faces`
    with their corners from each face's first): (vertex colours, face colours, modes), each colours
    None or a list of tuples of binary32 bits, modes the Kv + Kf modes. Raises FormatError on
    anything the text refuses."""
    need(minor >= 8, 'section 0x0b (colours) is format 3.8\'s, and the file says it is 3.%d' % minor)
    need(len(faces) == F, 'colours: %d faces for F = %d' % (len(faces), F))
    Kv, Kf, modes, stream = parse_header(payload, V, F)
    seen('colors: Kv=%d Kf=%d' % (Kv, Kf))
    for mode in modes:
        seen('colors: mode %s' % ('float' if mode == 0 else 'decimal' if mode <= 10 else 'binary'))
    rd = g.RangeDecoder(stream)
    t = Models()

    def component(pred, key, mode, what):
        """(binary32 bits, the integer later predictions use)"""
        r = code_residual(rd, key)
        u, why = value_of(pred + r, mode)
        need(why is None, 'colours: %s: %s' % (what, why))
        q = integer_of(u, mode) if INTEGER_OF_DECODED else pred + r
        if q != pred + r:
            seen('colors: decoded integer not the coded one')
        return u, q

    vcols = fcols = None
    if Kv:
        vm = modes[:Kv]
        nexts = corner_vertices(V, faces)
        vcols, vints = [], []
        for v in range(V):
            nb = neighbours(v, nexts)
            seen('colors: vertex n=%d' % min(len(nb), 2) if nb else 'colors: vertex n=0, %s' % (
                'previous' if v else 'first'))
            if len(nb) == MAX_NEIGHBOURS and sum(u < v for u in nexts[v]) > MAX_NEIGHBOURS:
                seen('colors: vertex with more than 8 decoded neighbours')
            val, it = [], []
            for j in range(Kv):
                p, key = vertex_prediction(v, nb, vints, j, vm[j])
                u, q = component(p, t('vertex%d' % key), vm[j], 'vertex %d component %d' % (v, j))
                val.append(u)
                it.append(q)
            vcols.append(tuple(val))
            vints.append(it)
    if Kf:
        fm = modes[Kv:]
        last = [None] * V
        fcols, fints = [], []
        for gi, f in enumerate(faces):
            ls = [last[v] for v in f if last[v] is not None]
            nb = max(ls) if ls else None
            seen('colors: face %s' % ('neighbour' if nb is not None else 'previous' if gi else 'first'))
            if nb is not None and nb != gi - 1:
                seen('colors: face neighbour not the previous face')
            val, it = [], []
            for j in range(Kf):
                p, key = face_prediction(gi, nb, fints, j, fm[j])
                u, q = component(p, t('face%d' % key), fm[j], 'face %d component %d' % (gi, j))
                val.append(u)
                it.append(q)
            fcols.append(tuple(val))
            fints.append(it)
            for v in f:
                last[v] = gi
    rd.finish()
    return vcols, fcols, modes


# ---------------- the reference encoder's choices ("What the encoder writes") ----------------
def held(values, mode):
    """Whether every binary32 (bits) of values is a value of the grid `mode` names, exactly."""
    for u in values:
        if u & 0x7F800000 == 0x7F800000:
            return False
        q = integer_of(u, mode)
        if not -LIM <= q <= LIM or g.f32_of_rational(q, den_of(mode)) != u:   # (-0: never)
            return False
    return True


def lossless_mode(values):
    """The decimal grid of the fewest decimals (0..9) that holds all values exactly, else float bits."""
    for k in range(10):
        if held(values, 1 + k):
            return 1 + k
    return 0


def quantized_mode(values, bits):
    """--quantize-color BITS: the binary grid of step 2^-BITS, unless a value is 2^(40 - BITS) or more
    in magnitude (or not finite), when the component stays exact."""
    for u in values:
        y = g.bits_f32(u)
        if not math.isfinite(y) or abs(y) >= 2.0 ** (40 - bits):
            return lossless_mode(values)
    return 16 + bits


def on_grid(u, mode):
    """Binary32 bits u rounded to the binary grid of step 2^-b (halves to even, -0 to 0): the value
    the decoder gives back, the binary32 nearest q * 2^-b."""
    b = mode - 16
    z = g.bits_f32(u) * float(1 << b)     # exact
    q = round(z)                          # Python rounds a float's halves to even
    if z - math.floor(z) == 0.5:
        seen('colors: --quantize-color halfway')
    return g.f32_of_rational(q, 1 << b)


def choose_modes(values, K, quantize=None):
    cols = [[v[j] for v in values] for j in range(K)]
    if quantize:
        return [quantized_mode(c, quantize) for c in cols]
    return [lossless_mode(c) for c in cols]


def rounded(values, modes):
    """values with each component on its binary grid (the values a decoder gives back)."""
    return [tuple(on_grid(u, m) if m >= 17 else u for u, m in zip(v, modes)) for v in values]


def residuals_of(vcols, fcols, V, faces, modes):
    """The residuals of the section's stream, in stream order, of values already on their modes'
    grids."""
    Kv = len(vcols[0]) if vcols else 0
    Kf = len(fcols[0]) if fcols else 0
    vm, fm = modes[:Kv], modes[Kv:]
    out = []

    def component(u, pred, mode):
        q = integer_of(u, mode)
        assert value_of(q, mode) == (u, None), 'a value mode %d does not hold' % mode
        out.append(q - pred)
        return q

    if Kv:
        nexts = corner_vertices(V, faces)
        vints = []
        for v in range(V):
            nb = neighbours(v, nexts)
            vints.append([component(vcols[v][j], vertex_prediction(v, nb, vints, j, vm[j])[0], vm[j])
                          for j in range(Kv)])
    if Kf:
        last = [None] * V
        fints = []
        for gi, f in enumerate(faces):
            ls = [last[v] for v in f if last[v] is not None]
            nb = max(ls) if ls else None
            fints.append([component(fcols[gi][j], face_prediction(gi, nb, fints, j, fm[j])[0], fm[j])
                          for j in range(Kf)])
            for v in f:
                last[v] = gi
    return out


def pack(Kv, Kf, modes, residuals, V, faces, flags=None):
    """The payload of given residuals (stream order), each through the model the text names for its
    place; flags: the flags byte (Kv | Kf << 3 unless given)."""
    enc = g.RangeEncoder()
    t = Models()
    it = iter(residuals)
    if Kv:
        nexts = corner_vertices(V, faces)
        for v in range(V):
            n = len(neighbours(v, nexts))
            for j in range(Kv):
                code_residual(enc, t('vertex%d' % (3 * j + min(n, 2))), next(it))
    if Kf:
        last = [None] * V
        for gi, f in enumerate(faces):
            nb = any(last[v] is not None for v in f)
            for j in range(Kf):
                code_residual(enc, t('face%d' % (2 * j + (0 if nb else 1))), next(it))
            for v in f:
                last[v] = gi
    return bytes([Kv | Kf << 3 if flags is None else flags]) + bytes(modes) + enc.finish()


def encode_colors(vcols, fcols, V, faces, quantize=None, modes=None):
    """The section of vertex colours vcols (V tuples of binary32 bits, or None) and face colours fcols
    (one tuple per face of `faces`, or None) over the output mesh before an order section, with the
    reference encoder's modes (lossless, or --quantize-color `quantize`) or the given ones."""
    Kv = len(vcols[0]) if vcols else 0
    Kf = len(fcols[0]) if fcols else 0
    assert Kv in (0, 3, 4) and Kf in (0, 1, 3, 4) and (Kv or Kf)
    assert not vcols or len(vcols) == V
    assert not fcols or len(fcols) == len(faces)
    if modes is None:
        modes = (choose_modes(vcols, Kv, quantize) if Kv else []) + (choose_modes(fcols, Kf, quantize) if Kf else [])
    vcols = vcols and rounded(vcols, modes[:Kv])
    fcols = fcols and rounded(fcols, modes[Kv:])
    return pack(Kv, Kf, modes, residuals_of(vcols, fcols, V, faces, modes), V, faces)


def _selftest():
    """Round trips through encode_colors and decode_colors on small meshes: every mode, escapes,
    neighbours beyond 8, and the header's refusals."""
    import random
    rng = random.Random(1)
    f32 = lambda x: g.f32_bits_of_double(x)
    # a 5x4 grid of quads plus a fan vertex with 10 neighbours
    n = 5
    faces = [[j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i] for j in range(3) for i in range(4)]
    hub = 4 * n
    ring = list(range(n)) + [2 * n - 1, 3 * n - 1, 4 * n - 1, 4 * n - 2, 4 * n - 3]
    for a, b in zip(ring, ring[1:]):
        faces.append([hub, b, a])
    V = hub + 2     # one vertex in no face
    fails = 0
    cases = []
    cases.append(('uchar', [tuple(f32(rng.randint(0, 255)) for _ in range(3)) for _ in range(V)],
                  [tuple(f32(rng.randint(0, 255)) for _ in range(1)) for _ in faces], None))
    cases.append(('unit', [tuple(f32(rng.random()) for _ in range(4)) for _ in range(V)],
                  [tuple(f32(round(rng.random(), 2)) for _ in range(3)) for _ in faces], None))
    cases.append(('q8', [tuple(f32(rng.random()) for _ in range(4)) for _ in range(V)],
                  [tuple(f32(rng.random()) for _ in range(4)) for _ in faces], 8))
    ext = [3e38, -3e38, 1e-45, -0.0, 0.0, 1.5, -2.25]
    cases.append(('extremes', [tuple(f32(rng.choice(ext)) for _ in range(3)) for _ in range(V)], None, None))
    cases.append(('big', None, [tuple(f32(rng.choice([5e11, -5e11, 0.5, 1.0])) for _ in range(3)) for _ in faces], 12))
    for name, vc, fc, qb in cases:
        p = encode_colors(vc, fc, V, faces, qb)
        try:
            dv, df, modes = decode_colors(p, V, len(faces), faces)
        except FormatError as e:
            print('selftest %s: refused: %s' % (name, e))
            fails += 1
            continue
        Kv = len(vc[0]) if vc else 0
        want_v = rounded(vc, modes[:Kv]) if vc else None
        want_f = rounded(fc, modes[Kv:]) if fc else None
        if dv != want_v or df != want_f:
            print('selftest %s: decodes to other values' % name)
            fails += 1
        print('selftest %s: %d bytes, modes %s' % (name, len(p), [mode_name(m) for m in modes]))
        for bad, why in ((bytes([p[0] | 0x40]) + p[1:], 'reserved bit'), (bytes([p[0] & ~7 | 2]) + p[1:], 'Kv 2'),
                         (bytes([0]) + p[1:], 'both zero'), (p[:-1], 'a byte short'), (p + b'\0', 'a zero more'),
                         (p[:1] + bytes([11]) + p[2:], 'mode 11')):
            try:
                decode_colors(bad, V, len(faces), faces)
                if 'short' not in why:   # (a byte short may decode to other values: "Compact ends")
                    print('selftest %s: %s not refused' % (name, why))
                    fails += 1
            except FormatError:
                pass
    return fails


if __name__ == '__main__':
    import sys
    sys.exit(1 if _selftest() else 0)
