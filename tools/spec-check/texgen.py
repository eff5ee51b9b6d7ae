#!/usr/bin/env python3
"""texgen.py IN.obj OUT.obj SEED MODE: IN's positions and faces with texture coordinates (OBJ `vt`),
for check.sh, so that qsppoly.py meets every rule of qsp_format.md's texture coordinates section:
faces in up to three charts (a vertex's corners name up to three values: seams, picks), faces and
single corners naming none, corners naming another vertex's value (far references), equal values on
separate lines, values no corner names, all in shuffled order (--keep-order has a permutation to keep).
MODE picks the components: `uv` (u on a 3-decimal grid, v float32 bits), `u` (one component, float
bits with extremes: escapes, infinite parallelograms, subnormals, -0), `uvw` (float extremes, integers
near 2^39 so that parallelograms clamp, and a 2-decimal grid) or `uh` (float bits, and values
±(2^21 + n/4) that only a 1-decimal grid holds, y * 10 halfway between two integers for odd n).
MODE `bent` does not read IN: a 24x24 grid whose texture coordinates bend smoothly (a quadratic map
in two charts meeting at a seam), so that the corrections pay and the grid lines run, with a few
quads split into triangles, pairs of quads merged into hexagons, each with a flap: a quad on the
hexagon's chord (its corners two apart from one side, three from the other), 8 more hexagons with
a flap (a quad, or a triangle) apart, one face naming none, and values no corner names; u in a
decimal grid, v in float bits (a value no corner names needs them; two rows of tiny v between
rows of equal v, so that the float predictions' binary64 sums lose bits), for --float32 or --quantize-uv."""
import random
import struct
import sys

src, out, seed, mode = sys.argv[1], sys.argv[2], int(sys.argv[3]), sys.argv[4]
random.seed(seed)
f32 = lambda x: struct.unpack('<f', struct.pack('<f', x))[0]
EXTREMES = ['3e+38', '-3e+38', '3.4028235e+38', '-3.4028235e+38', '1e-38', '-2.5', '0', '-0',
            '1.4e-45', '0.1', '-1.17549435e-38']
BIG = ['549755813888', '-549755813888', '549755748352', '0', '7', '-1099511562240']


def component(kind, x, y):
    if kind == 'dec3':
        return '%.3f' % (x * 0.137 + random.randint(0, 9) * 0.001)
    if kind == 'dec2':
        return '%.2f' % (y * 0.71 - random.randint(0, 99) * 0.01)
    if kind == 'float':
        return '%.9g' % f32(y * 0.173 + random.random() * 1e-3)
    if kind == 'half':
        return '%.9g' % (random.choice([-1, 1]) * (2 ** 21 + random.randint(0, 4 * 2 ** 21 - 1) / 4))
    if kind == 'extreme':
        return random.choice(EXTREMES)
    return random.choice(BIG)


def bent():
    """The `bent` mesh: (lines of positions, faces, per face the (vertex, chart) of each corner or
    None, uv of a (vertex, chart))."""
    n = 25
    lines = ['v %d %d %.3f\n' % (i, j, 0.25 * ((i - 12) ** 2 - (j - 9) ** 2) / 144) for j in range(n) for i in range(n)]
    flap_at = {}
    faces = []
    done = set()
    for j in range(n - 1):
        for i in range(n - 1):
            if (i, j) in done:
                continue
            a = j * n + i + 1
            r = random.random()
            if r < 0.04 and i + 2 < n and (i + 1, j) not in done and i != 11:   # a hexagon, and its flap
                done.add((i + 1, j))
                faces.append([a, a + 1, a + 2, a + n + 2, a + n + 1, a + n])
                lines.append('v %d.5 %d.5 1\n' % (i + 1, j))
                lines.append('v %d.5 %d.5 1\n' % (i, j))
                x, y = len(lines) - 1, len(lines)
                chord = [a + 1, a + n + 1] if random.random() < 0.5 else [a + n + 1, a + 1]
                faces.append(chord + [x, y])
                flap_at[x] = flap_at[y] = (i + 0.5, j + 0.5)
            elif r < 0.08:
                faces += [[a, a + 1, a + n + 1], [a, a + n + 1, a + n]]
            else:
                faces.append([a, a + 1, a + n + 1, a + n])
    for c in range(8):  # apart: a hexagon and a flap on its chord, each corner of the hexagon two
        # apart from one corner of the chord and three from the other (both orientations)
        base = len(lines) + 1
        for k in range(6):
            lines.append('v %d %.1f %d\n' % (40 + 3 * c + (k in (2, 3)) - (k in (0, 5)), (k in (0, 1, 2)) * 1.5, c))
        lines += ['v %d 0.75 %d\n' % (40 + 3 * c, c + 1), 'v %d.5 0.75 %d\n' % (40 + 3 * c, c + 1)]
        hexagon = [base + k for k in range(6)]
        chord = [base + 1, base + 4] if c % 2 else [base + 4, base + 1]
        flap = chord + ([base + 6, base + 7] if c < 6 else [base + 6])
        for k, v in enumerate(hexagon + [base + 6, base + 7]):
            flap_at[v] = (30 + 3 * c + k % 3, 30 + k // 3 + (k > 5))
        faces += [flap, hexagon] if c % 4 < 2 else [hexagon, flap]
    corners = []
    for f in faces:
        if f[0] == 4 * n + 6:
            corners.append(None)                                    # a face naming none
            continue
        xs = [flap_at[v][0] if v in flap_at else (v - 1) % n for v in f]
        chart = 0 if sum(xs) < 12 * len(xs) else 1                  # the seam: column 12
        corners.append([(v, chart) for v in f])

    def uv(v, chart):
        i, j = flap_at[v] if v in flap_at else ((v - 1) % n, (v - 1) // n)
        s, t = (i, j) if chart == 0 else (24 - i, j)
        u = 0.02 * s + 0.0009 * s * t - 0.0004 * t * t + 0.5 * chart
        w = 0.021 * t + 0.0006 * s * s + 0.0003 * s * t
        if (t, chart) in ((5, 1), (17, 0)):   # a row of tiny v between rows of equal v: binary64
            w = 1e-20 * (1 + 0.37 * s)         # sums in term order lose the tiny terms
        elif (t, chart) in ((4, 1), (6, 1), (16, 0), (18, 0)):
            w = 0.5
        return '%.9g %.9g' % (f32(u), f32(w))
    return lines, faces, corners, uv

def write_obj(lines, vts, faces, names):
    """The mesh's v lines, its values as vt lines in a shuffled order, and faces naming them (None: none)."""
    order = list(range(len(vts)))
    random.shuffle(order)
    at = {old: new for new, old in enumerate(order)}
    with open(out, 'w') as o:
        o.writelines(lines)
        for old in order:
            o.write('vt %s\n' % vts[old])
        for f, nm in zip(faces, names):
            o.write('f %s\n' % ' '.join('%d' % v if x is None else '%d/%d' % (v, at[x] + 1) for v, x in zip(f, nm)))

if mode == 'bent':
    lines, faces, corners, uv = bent()
    vts, at_value = [], {}
    for cs in corners:
        for vc in cs or []:
            if vc not in at_value:
                at_value[vc] = len(vts)
                vts.append(uv(*vc))
    names = [[None] * len(f) if cs is None else [at_value[vc] for vc in cs] for f, cs in zip(faces, corners)]
    vts += ['%.9g %.9g' % (f32(random.random()), f32(random.random())), '0.5 1.17549435e-38']  # (v: float bits)
    write_obj(lines, vts, faces, names)
    sys.exit(0)
kinds = {'uv': ['dec3', 'float'], 'u': ['extreme'], 'uvw': ['extreme', 'big', 'dec2'], 'uh': ['float', 'half']}[mode]
lines, pos, faces = [], [], []
for line in open(src):
    w = line.split()
    if w and w[0] == 'v':
        pos.append((float(w[1]), float(w[2])))
        lines.append(line)
    elif w and w[0] == 'f':
        faces.append([int(x.split('/')[0]) for x in w[1:]])
vts = []            # the values, as text
chart_value = {}    # (vertex, chart) -> index into vts
names = []
for fi, f in enumerate(faces):
    r = random.random()
    if r < 0.05:
        names.append([None] * len(f))
        continue
    chart = 0 if r < 0.6 else 1 if r < 0.85 else 2
    nm = []
    for v in f:
        q = random.random()
        if q < 0.03:
            nm.append(None)
        elif q < 0.07 and vts:
            nm.append(random.randrange(len(vts)))     # another vertex's value, mostly: far
        else:
            if (v, chart) not in chart_value:
                x, y = pos[v - 1]
                text = ' '.join(component(k, x + 3 * chart, y) for k in kinds)
                if random.random() < 0.05 and vts:
                    text = random.choice(vts)          # an equal value on a line of its own
                chart_value[v, chart] = len(vts)
                vts.append(text)
            nm.append(chart_value[v, chart])
    names.append(nm)
for _ in range(3):  # values no corner names
    vts.append(' '.join(component(k, random.random(), random.random()) for k in kinds))
write_obj(lines, vts, faces, names)
