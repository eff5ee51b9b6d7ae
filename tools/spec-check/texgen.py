#!/usr/bin/env python3
"""texgen.py IN.obj OUT.obj SEED MODE: IN's positions and faces with texture coordinates (OBJ `vt`),
for check.sh, so that qsppoly.py meets every rule of qsp_format.md's texture coordinates section:
faces in up to three charts (a vertex's corners name up to three values: seams, picks), faces and
single corners naming none, corners naming another vertex's value (far references), equal values on
separate lines, values no corner names, all in shuffled order (--keep-order has a permutation to keep).
MODE picks the components: `uv` (u on a 3-decimal grid, v float32 bits), `u` (one component, float
bits with extremes: escapes, infinite parallelograms, subnormals, -0) or `uvw` (float extremes, integers
near 2^39 so that parallelograms clamp, and a 2-decimal grid)."""
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
    if kind == 'extreme':
        return random.choice(EXTREMES)
    return random.choice(BIG)


kinds = {'uv': ['dec3', 'float'], 'u': ['extreme'], 'uvw': ['extreme', 'big', 'dec2']}[mode]
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
order = list(range(len(vts)))
random.shuffle(order)
at = {old: new for new, old in enumerate(order)}
with open(out, 'w') as o:
    o.writelines(lines)
    for old in order:
        o.write('vt %s\n' % vts[old])
    for f, nm in zip(faces, names):
        o.write('f %s\n' % ' '.join('%d' % v if x is None else '%d/%d' % (v, at[x] + 1) for v, x in zip(f, nm)))
