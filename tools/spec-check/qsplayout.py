"""The coding order and stencils of a .qsp file's geometry section, built from the text alone.

qspgeo.py's companion, written by the same reviewer from format-spec/qsp_format.md ("Topology
section", "Grid layout") and format-spec/geometry_section.md ("Coding orders and stencils") without
reading the codec's C++: it decodes the topology stream, lays the grids out and builds both coding
orders, so that qspgeo.py checks that text against the stencils the reference decoder uses.

stencils(topology_payload, V, U, layout_order) -> (coding, stencil list) in dump_stencils' form.
"""
import qspgeo as g

NONE = g.NONE


# ---------------- qsp_format.md "Topology section" ----------------
class Component:
    """One component's TopologyCode: kind; a, b, twist (annulus, torus); the schematic (kinds 0, 1)."""

    def __init__(self, kind):
        self.kind = kind
        self.a = self.b = self.twist = 0
        self.next = []      # next[d]: the following dart ccw around d's face
        self.hole = []      # per face (by lowest dart label)
        self.corner = []    # per dart
        self.length = []    # per edge


def twin(d):
    return d ^ 1


class Chains:
    """Paths with linked endpoints ("face chains", "vertex paths"): end[h] = t, end[t] = h, length at both."""

    def __init__(self):
        self.end = []
        self.len = []

    def add(self):
        d = len(self.end)
        self.end.append(d)
        self.len.append(1)

    def join(self, tail, head):
        """Joins the path ending at `tail` with the one starting at `head`."""
        h0 = self.end[tail]
        if h0 == head:                 # its own head: a closed cycle, no endpoints
            return
        t1 = self.end[head]
        n = self.len[tail] + self.len[head]
        self.end[h0], self.end[t1] = t1, h0
        self.len[h0] = self.len[t1] = n


def orbits(n, step):
    """Orbits of the permutation `step` of 0..n-1 by lowest member: (orbit of each, members of each)."""
    of = [NONE] * n
    out = []
    for d in range(n):
        if of[d] == NONE:
            orbit = []
            x = d
            while of[x] == NONE:
                of[x] = len(out)
                orbit.append(x)
                x = step(x)
            out.append(orbit)
    return of, out


def decode_topology(payload, C):
    rd = g.RangeDecoder(payload)
    T = {}

    def table(name):
        if name not in T:
            T[name] = g.Table()
        return T[name]

    comps = []
    # 1. kinds and sizes
    for _ in range(C):
        hi = rd.bit(table('kind')[0])
        lo = rd.bit(table('kind')[1 + hi])
        c = Component(2 * hi + lo)
        if c.kind >= 2:
            c.a = rd.integer(table('size_a'))
            c.b = rd.integer(table('size_b'))
            if c.kind == 3:
                c.twist = rd.integer(table('twist'))
        comps.append(c)
    schem = [c for c in comps if c.kind <= 1]
    # 2. next_ref
    for c in schem:
        nxt = [NONE, NONE]
        pool = {0, 1}
        face, vert = Chains(), Chains()
        for _ in range(2):
            face.add()
            vert.add()
        i = 0
        while i < len(nxt):
            ctx = 5 * (min(face.len[i], 5) - 1) + min(vert.len[twin(i)], 5) - 1
            vc = vert.end[twin(i)]
            fc = face.end[i]
            g.need(vc in pool and fc in pool, 'vc, fc not in Pool')
            if rd.bit(table('is_new')[ctx]):
                z = len(nxt)
                nxt += [NONE, NONE]
                pool |= {z, z + 1}
                for _ in range(2):
                    face.add()
                    vert.add()
            elif rd.bit(table('is_vertex')[ctx]):
                z = vc
            elif fc != vc and rd.bit(table('is_face')[ctx]):
                z = fc
            else:
                others = sorted(pool - {vc, fc})
                g.need(others, 'no N in Pool')
                N = others[-1]
                if rd.bit(table('is_newest')[0]):
                    z = N
                else:
                    step = g.unzigzag(rd.integer(table('other_step')))
                    members = sorted(pool)
                    rank = sum(1 for x in members if x < i) + step
                    g.need(0 <= rank < len(members), 'other_step outside Pool')
                    z = members[rank]
                    g.need(z not in (vc, fc, N), 'other_step names vc, fc or N')
            nxt[i] = z
            pool.discard(z)
            face.join(i, z)
            vert.join(twin(i), z)
            i += 1
        c.next = nxt
    # faces (orbits of next) and vertices (orbits of sigma), numbered by their lowest dart
    for c in schem:
        c.face_of, c.faces = orbits(len(c.next), lambda d: c.next[d])
        c.vert_of, c.verts = orbits(len(c.next), lambda d: c.next[twin(d)])
    # 3. holes
    for c in schem:
        h = rd.integer(table('hole_count'))
        c.hole = [False] * len(c.faces)
        for f, orbit in enumerate(c.faces):
            if h == 0:
                break
            if len(orbit) < 4 or rd.bit(table('is_hole')[min(len(orbit) - 4, 3)]):
                c.hole[f] = True
                h -= 1
        g.need(h == 0, 'hole count not reached')
        g.need(all(c.hole[f] or len(o) >= 4 for f, o in enumerate(c.faces)), 'patch with < 4 darts')
    # 4. corners
    for c in schem:
        D = len(c.next)
        decided = [False] * D
        c.corner = [False] * D
        for f, orbit in enumerate(c.faces):
            if c.hole[f]:
                for d in orbit:
                    decided[d] = True
        known_c = [0] * len(c.verts)
        known_n = [0] * len(c.verts)
        for d in range(D):
            if decided[d]:
                known_n[c.vert_of[d]] += 1
        for f, orbit in enumerate(c.faces):
            if c.hole[f]:
                continue
            needed = 4
            for idx, d in enumerate(orbit):
                remaining = len(orbit) - idx
                v = c.vert_of[d]
                if needed == 0:
                    isc = False
                elif needed == remaining:
                    isc = True
                else:
                    deg = min(max(len(c.verts[v]), 2), 6) - 2
                    ctx = ((deg * 4 + min(known_c[v], 3)) * 3 + min(known_n[v], 2)) * 3 + min(remaining - needed, 3) - 1
                    isc = bool(rd.bit(table('corner')[ctx]))
                c.corner[d] = isc
                decided[d] = True
                if isc:
                    needed -= 1
                    known_c[v] += 1
                else:
                    known_n[v] += 1
    # 5. edge lengths
    for c in schem:
        E = len(c.next) // 2
        cons = []
        c.sides = {}
        for f, orbit in enumerate(c.faces):
            if c.hole[f]:
                continue
            k = next(ix for ix, d in enumerate(orbit) if c.corner[d])
            walk = orbit[k:] + orbit[:k]
            sides = []
            for d in walk:
                if c.corner[d]:
                    sides.append([])
                sides[-1].append(d)
            g.need(len(sides) == 4, 'patch without four sides')
            c.sides[f] = sides
            for s0, s1 in ((0, 2), (1, 3)):
                coef = {}
                for d in sides[s0]:
                    coef[d >> 1] = coef.get(d >> 1, 0) + 1
                for d in sides[s1]:
                    coef[d >> 1] = coef.get(d >> 1, 0) - 1
                cons.append({e: x for e, x in coef.items() if x != 0})
        on_hole = [False] * E
        for f, orbit in enumerate(c.faces):
            if c.hole[f]:
                for d in orbit:
                    on_hole[d >> 1] = True
        length = [None] * E
        for e in range(E):
            if length[e] is not None:
                continue
            length[e] = rd.integer(table('length%d' % on_hole[e])) + 1
            changed = True
            while changed:
                changed = False
                for con in cons:
                    unknown = [x for x in con if length[x] is None]
                    if len(unknown) == 1:
                        u = unknown[0]
                        rest = sum(x * length[y] for y, x in con.items() if y != u)
                        g.need(rest % con[u] == 0, 'length not an integer')
                        length[u] = -rest // con[u]
                        g.need(length[u] >= 1, 'length below 1')
                        changed = True
        for con in cons:
            g.need(sum(x * length[y] for y, x in con.items()) == 0, 'constraint fails')
        c.length = length
    rd.finish()
    return comps


# ---------------- qsp_format.md "Grid layout" ----------------
class Patch:
    """A patch of the layout: sides a, b; P[(i, j)] its points; ring[r] its boundary ring."""


def layout_schematic(c):
    """Vertex numbering of a schematic component; fills c.patches, c.nsv (schematic vertices),
    c.edge_inner[e][k], c.V, c.kind_of[v] ('sv', 'edge', 'inner') and the mesh faces c.quads."""
    c.nsv = len(c.verts)
    n = c.nsv
    E = len(c.next) // 2
    c.edge_inner = []
    c.kind_of = ['sv'] * c.nsv
    for e in range(E):
        pts = [None] + list(range(n, n + c.length[e] - 1))
        c.edge_inner.append(pts)
        c.kind_of += ['edge'] * (c.length[e] - 1)
        n += c.length[e] - 1
    c.patches = []
    for f, orbit in enumerate(c.faces):
        if c.hole[f]:
            continue
        p = Patch()
        c0 = min(d for d in orbit if c.corner[d])
        k = orbit.index(c0)
        walk = orbit[k:] + orbit[:k]
        ring = []
        for d in walk:
            l = c.length[d >> 1]
            ring.append(c.vert_of[d])
            for kk in range(1, l):
                ring.append(c.edge_inner[d >> 1][kk if d % 2 == 0 else l - kk])
        sides = []
        for d in walk:
            if c.corner[d]:
                sides.append(0)
            sides[-1] += c.length[d >> 1]
        a, b = sides[0], sides[1]
        g.need(sides[2] == a and sides[3] == b and len(ring) == 2 * (a + b), 'patch sides')
        p.a, p.b, p.ring = a, b, ring
        P = {}
        for r in range(2 * (a + b)):
            P[ring_pos(a, b, r)] = ring[r]
        for j in range(1, b):
            for i in range(1, a):
                P[(i, j)] = n
                n += 1
                c.kind_of.append('inner')
        p.P = P
        c.patches.append(p)
    c.V = n
    c.quads = []
    for p in c.patches:
        for j in range(p.b):
            for i in range(p.a):
                c.quads.append((p.P[(i, j)], p.P[(i + 1, j)], p.P[(i + 1, j + 1)], p.P[(i, j + 1)]))


def ring_pos(a, b, r):
    """Ring position r of an (a, b) patch, counter-clockwise from c0 ("Across a patch")."""
    if r < a:
        return (r, 0)
    if r < a + b:
        return (a, r - a)
    if r < 2 * a + b:
        return (2 * a + b - r, b)
    return (0, 2 * a + 2 * b - r)


def ring_side(a, b, r):
    return 0 if r < a else 1 if r < a + b else 2 if r < 2 * a + b else 3


# ---------------- geometry_section.md "Coding orders and stencils" ----------------
def blank():
    d = {f: NONE for f in g.FIELDS}
    d.update(far_dist=0, e_dist=0, n_dist=0, xnum=0, xden=0)
    return d


def grid_stencils(c, patch_extra):
    """Annulus and torus: layout-order stencils, and patch order's extra fields if patch_extra."""
    a, rows = c.a, c.b + 1 if c.kind == 2 else c.b
    st = []
    for y in range(rows):
        for x in range(a):
            s = blank()
            at = lambda xx, yy: yy * a + xx
            if x >= 1: s['w'] = at(x - 1, y)
            if x >= 2: s['ww'] = at(x - 2, y)
            if y >= 1: s['s'] = at(x, y - 1)
            if x >= 1 and y >= 1: s['sw'] = at(x - 1, y - 1)
            if patch_extra and x >= 1 and y >= 1:
                if x + 1 < a: s['se'] = at(x + 1, y - 1)
                if y >= 2: s['ss'], s['ssw'] = at(x, y - 2), at(x - 1, y - 2)
                if x >= 2: s['sww'] = at(x - 2, y - 1)
            st.append(s)
    return st


def layout_order_stencils(c):
    st = [blank() for _ in range(c.V)]
    # schematic vertices
    adj = [set() for _ in range(c.nsv)]
    for d in range(len(c.next)):
        u, v = c.vert_of[d], c.vert_of[twin(d)]
        adj[u].add(v)
    for v in range(c.nsv):
        below = [u for u in adj[v] if u < v]
        if below:
            st[v]['w'] = max(below)
        elif v > 0:
            st[v]['w'] = v - 1
    # edge-inner points
    for e, pts in enumerate(c.edge_inner):
        l = len(pts)  # = length
        u = c.vert_of[2 * e]
        for k in range(1, l):
            s = st[pts[k]]
            s['w'] = u if k == 1 else pts[k - 1]
            if k == 2:
                s['ww'] = u
            elif k > 2:
                s['ww'] = pts[k - 2]
            s['far'] = c.vert_of[2 * e + 1]
            s['far_dist'] = l - k
    # patch-inner points
    for p in c.patches:
        a, b, P = p.a, p.b, p.P
        for j in range(1, b):
            for i in range(1, a):
                s = st[P[(i, j)]]
                s['w'] = P[(i - 1, j)]
                if i >= 2: s['ww'] = P[(i - 2, j)]
                s['s'], s['sw'] = P[(i, j - 1)], P[(i - 1, j - 1)]
                s['e'], s['es'], s['e_dist'] = P[(a, j)], P[(a, j - 1)], a - i
                s['n'], s['nw'], s['n_dist'] = P[(i, b)], P[(i - 1, b)], b - j
    # across a patch
    best = {}  # edge-inner point -> (distance, o, ow, ofar)
    for p in c.patches:
        a, b, P = p.a, p.b, p.P
        for r in range(2 * (a + b)):
            x = p.ring[r]
            i, j = ring_pos(a, b, r)
            side = ring_side(a, b, r)
            s = st[x]
            if c.kind_of[x] == 'sv':
                if i in (0, a) and j in (0, b):
                    if s['x2'] == NONE:
                        c0, c1, c2 = P[(a - i, b - j)], P[(a - i, j)], P[(i, b - j)]
                        if c0 < x and c1 < x and c2 < x:
                            s['x0'], s['x1'], s['x2'] = c0, c1, c2
                            s['xnum'] = s['xden'] = 0
                elif s['x0'] == NONE:
                    if side in (0, 2):
                        q0, q1, num, den = P[(0, j)], P[(a, j)], i, a
                    else:
                        q0, q1, num, den = P[(i, 0)], P[(i, b)], j, b
                    if q0 < x and q1 < x:
                        s['x0'], s['x1'], s['xnum'], s['xden'] = q0, q1, num, den
            elif c.kind_of[x] == 'edge':
                delta = ((1, 0), (0, 1), (-1, 0), (0, -1))[side]
                dr = -1 if p.ring[(r - 1) % len(p.ring)] == s['w'] else 1
                wpos = (i + dr * delta[0], j + dr * delta[1])
                fpos = (i - dr * s['far_dist'] * delta[0], j - dr * s['far_dist'] * delta[1])
                if not all(0 <= q[0] <= a and 0 <= q[1] <= b for q in (wpos, fpos)):
                    continue
                opp = (lambda q: (q[0], b - q[1])) if side in (0, 2) else (lambda q: (a - q[0], q[1]))
                o, ow, of = P[opp((i, j))], P[opp(wpos)], P[opp(fpos)]
                if o < x and ow < x:
                    dist = 2 * (b if side in (0, 2) else a) + (0 if of < x else 1)
                    if x not in best or dist < best[x][0]:
                        best[x] = (dist, o, ow, of if of < x else NONE)
    for x, (_, o, ow, of) in best.items():
        st[x]['o'], st[x]['ow'], st[x]['ofar'] = o, ow, of
    return st


def patch_order_stencils(c):
    """Patch order of a schematic component: (coding, stencils by coding position)."""
    V = c.V
    patches = c.patches
    entries = [[] for _ in range(V)]   # ring entries of each point: (patch, ring position)
    for f, p in enumerate(patches):
        for r, x in enumerate(p.ring):
            entries[x].append((f, r))

    def across(x, f):
        if x == NONE or c.kind_of[x] != 'edge':
            return NONE
        for q, r in entries[x]:
            if q != f:
                pq = patches[q]
                i, j = ring_pos(pq.a, pq.b, r)
                side = ring_side(pq.a, pq.b, r)
                return pq.P[((i, 1), (pq.a - 1, j), (i, pq.b - 1), (1, j))[side]]
        return NONE

    pos = [NONE] * V               # coding position of each coded point
    coding = []
    sten = []
    cnt = [0] * len(patches)
    visited = [False] * len(patches)
    # faces of the layout containing each point, with the corner
    faces_at = [[] for _ in range(V)]
    for fi, q in enumerate(c.quads):
        for r in range(4):
            faces_at[q[r]].append((fi, r))
    for _ in range(len(patches)):
        # patch visiting
        cand = None
        for f in range(len(patches)):
            if visited[f]:
                continue
            rs = len(patches[f].ring)
            if cand is None:
                cand = f
                continue
            # larger cnt/ring_size wins, ties to the lowest f
            if cnt[f] * len(patches[cand].ring) > cnt[cand] * rs:
                cand = f
        f = cand
        visited[f] = True
        p = patches[f]
        a, b = p.a, p.b

        def turned(rot):
            ap, bp = (a, b) if rot % 2 == 0 else (b, a)

            def T0(i, j):
                if rot == 0: return p.P[(i, j)]
                if rot == 1: return p.P[(a - j, i)]
                if rot == 2: return p.P[(a - i, b - j)]
                return p.P[(j, b - i)]
            return ap, bp, T0
        best_rot, best_n = 0, -1
        for rot in range(4):
            ap, bp, T0 = turned(rot)
            n = sum(1 for i in range(ap + 1) if pos[T0(i, 0)] != NONE) + \
                sum(1 for j in range(1, bp + 1) if pos[T0(0, j)] != NONE)
            if n > best_n:
                best_rot, best_n = rot, n
        ap, bp, T0 = turned(best_rot)

        def T(i, j):
            if 0 <= i <= ap and 0 <= j <= bp:
                return T0(i, j)
            if i == -1 and 0 <= j <= bp:
                return across(T0(0, j), f)
            if j == -1 and 0 <= i <= ap:
                return across(T0(i, 0), f)
            return NONE

        def C(i, j):
            x = T(i, j)
            return pos[x] if x != NONE and pos[x] != NONE else NONE

        def coded(x):
            return x != NONE and pos[x] != NONE

        for j in range(bp + 1):
            for i in range(ap + 1):
                x = T(i, j)
                if pos[x] != NONE:
                    continue
                s = blank()
                w, sq, swq = C(i - 1, j), C(i, j - 1), C(i - 1, j - 1)
                if w != NONE and sq != NONE and swq != NONE:
                    # 1. frame: taken only when all three are coded (the text leaves the condition
                    # open; with w and s alone it would be the reference's finished-cell stencil)
                    s['w'], s['s'], s['sw'] = w, sq, swq
                    s['ww'], s['se'], s['ss'] = C(i - 2, j), C(i + 1, j - 1), C(i, j - 2)
                    if s['ww'] != NONE: s['sww'] = C(i - 2, j - 1)
                    if s['ss'] != NONE: s['ssw'] = C(i - 1, j - 2)
                    if i < ap and coded(T(ap, j)) and coded(T(ap, j - 1)):
                        s['e'], s['es'], s['e_dist'] = pos[T(ap, j)], pos[T(ap, j - 1)], ap - i
                    if j < bp and coded(T(i, bp)) and coded(T(i - 1, bp)):
                        s['n'], s['nw'], s['n_dist'] = pos[T(i, bp)], pos[T(i - 1, bp)], bp - j
                else:
                    done = False
                    for fi, r in faces_at[x]:
                        q = c.quads[fi]
                        cs = [q[(r + k) % 4] for k in (1, 2, 3)]
                        if all(pos[y] != NONE for y in cs):
                            s['s'], s['sw'], s['w'] = pos[cs[0]], pos[cs[1]], pos[cs[2]]
                            done = True
                            break
                    if done:
                        pass
                    elif C(i - 1, j) != NONE:
                        s['w'], s['ww'] = C(i - 1, j), C(i - 2, j)
                        if i < ap and coded(T(ap, j)):
                            s['far'], s['far_dist'] = pos[T(ap, j)], ap - i
                    elif C(i, j - 1) != NONE:
                        s['w'], s['ww'] = C(i, j - 1), C(i, j - 2)
                        if j < bp and coded(T(i, bp)):
                            s['far'], s['far_dist'] = pos[T(i, bp)], bp - j
                    else:
                        for fi, r in faces_at[x]:
                            q = c.quads[fi]
                            for k in (1, 3):
                                y = q[(r + k) % 4]
                                if pos[y] != NONE:
                                    s['w'] = pos[y]
                                    break
                            if s['w'] != NONE:
                                break
                pos[x] = len(coding)
                coding.append(x)
                sten.append(s)
                for q, r in entries[x]:
                    cnt[q] += 1
    g.need(len(coding) == V, 'patch order does not code every point')
    return coding, sten


def stencils(topology, C, U, layout_order):
    """(coding, stencils) of the whole file, components offset, then the U unreferenced vertices."""
    coding = []
    st = []
    base = 0
    for c in decode_topology(topology, C):
        if c.kind >= 2:
            cs = grid_stencils(c, not layout_order)
            cc = list(range(len(cs)))
        else:
            layout_schematic(c)
            if layout_order:
                cs = layout_order_stencils(c)
                cc = list(range(c.V))
            else:
                cc, cs = patch_order_stencils(c)
        for k, s in enumerate(cs):
            coding.append(base + cc[k])
            st.append({f: (x + base if f in g.FIELDS and x != NONE else x) for f, x in s.items()})
        base += len(cs)
    for u in range(U):
        s = blank()
        if base > 0:
            s['w'] = base - 1
        coding.append(base)
        st.append(s)
        base += 1
    return coding, st
