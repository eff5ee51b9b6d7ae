#!/usr/bin/env python3
"""The symmetry section of .qsp format 3.17 (qsp_format.md "Symmetry section"), written from the text:
its seeds, the mirror map they propagate over the layout's quads, and the mirror source and axis of
each coding position, which qspgeo.decode_geometry reads under tools bit 5 ("Mirror prediction" of
geometry_section.md); the map's vertex images are what the texture coordinates section's flag bit 5
reads (3.18, qsppoly.decode_texcoords).
"""
import qspgeo as g

need = g.need
NONE = g.NONE
MIRROR = 0x20          # geometry tools bit 5
TAG = 0x0f             # the section's tag
MINOR = 17             # its format version


def parse_symmetry(payload, F):
    """The seeds (face, image, turn, axis) of a symmetry section's payload, every field checked."""
    n, pos = g.read_varint(payload, 0)
    need(n <= F and n <= (len(payload) - pos) // 3,
         'symmetry section: seed count %d exceeds the faces or the data' % n)
    seeds = []
    for i in range(n):
        f, pos = g.read_varint(payload, pos)
        im, pos = g.read_varint(payload, pos)
        need(f < F and im < F, 'symmetry section: seed %d: face %d or image %d not below F = %d' % (i, f, im, F))
        need(pos < len(payload), 'symmetry section: seed %d: no turn and axis byte' % i)
        b = payload[pos]
        pos += 1
        need(b >> 4 == 0, 'symmetry section: seed %d: reserved bits set (byte 0x%02x)' % (i, b))
        need((b >> 2) & 3 != 3, 'symmetry section: seed %d: axis 3' % i)
        seeds.append((f, im, b & 3, b >> 2))
    need(pos == len(payload), 'symmetry section: %d bytes after the seeds' % (len(payload) - pos))
    return seeds


def mirror_map(V, quads, seeds):
    """(image, axis) per layout vertex (None where the map gives none), from the seeds, as "The mirror
    map" says: assign each seed, then propagate breadth-first across the faces' edges."""
    F = len(quads)
    half = {}              # (u, v) -> half-edge 4f + k, from corner k to corner k + 1 of face f
    for f, q in enumerate(quads):
        for k in range(4):
            half[q[k], q[(k + 1) % 4]] = 4 * f + k

    def twin(h):
        q = quads[h >> 2]
        k = h & 3
        return half.get((q[(k + 1) % 4], q[k]))

    face_image = [None] * F            # (g, r) per face
    is_image = [False] * F
    vimage = [None] * V
    vaxis = [None] * V
    queue = []

    def assign(f, im, r):
        if face_image[f] is not None:
            need(face_image[f] == (im, r), 'symmetry section: face %d has two images' % f)
            return
        need(not is_image[im], 'symmetry section: face %d is the image of two faces' % im)
        face_image[f] = (im, r)
        is_image[im] = True
        queue.append(f)
        for c in range(4):
            v, w = quads[f][c], quads[im][(r - c) % 4]
            if vimage[v] is None:
                vimage[v] = w
            else:
                need(vimage[v] == w, 'symmetry section: vertex %d has two images' % v)

    for i, (f, im, r, axis) in enumerate(seeds):
        queue.clear()
        assign(f, im, r)
        q = 0
        while q < len(queue):
            f1 = queue[q]
            q += 1
            g1, r1 = face_image[f1]
            for k in range(4):
                t = twin(4 * f1 + k)
                t2 = twin(4 * g1 + (r1 - k - 1) % 4)
                need((t is None) == (t2 is None),
                     'symmetry section: seed %d: face %d edge %d and its image: one on the boundary' % (i, f1, k))
                if t is None:
                    continue
                assign(t >> 2, t2 >> 2, ((t2 & 3) + 1 + (t & 3)) % 4)
        for f1 in queue:
            for v in quads[f1]:
                vaxis[v] = axis
    return vimage, vaxis


def mirror_sources(coding, vimage, vaxis):
    """Per coding position (layout vertices only): (mirror source, mirror axis), or None ("Mirror
    sources"). coding[k] is the layout vertex coded at k."""
    at = [None] * len(vimage)
    for k, v in enumerate(coding[:len(vimage)]):
        at[v] = k
    out = []
    for k, v in enumerate(coding[:len(vimage)]):
        w = vimage[v]
        out.append((at[w], vaxis[v]) if w is not None and w != v and at[w] < k else None)
    return out


def file_mirror(data, secs, V, quads, coding):
    """The mirror sources of a file's geometry section, or None without a symmetry section; the
    section's presence checked against tools bit 5 and the file's minor version."""
    m = file_map(data, secs, V, quads)
    return None if m is None else mirror_sources(coding, *m)


def file_map(data, secs, V, quads):
    """The mirror map of a file's symmetry section, (image, axis) per layout vertex as mirror_map
    gives them, or None without a symmetry section; the section's presence checked against tools
    bit 5 and the file's minor version."""
    geo = secs[3]
    has_bit = bool(geo[:1] and geo[0] & MIRROR)
    if TAG not in secs:
        need(not has_bit, 'geometry section: mirror prediction without a symmetry section')
        return None
    need(data[9] >= MINOR, 'section 0x0f (symmetry) is format 3.17\'s, and the file says it is 3.%d' % data[9])
    seeds = parse_symmetry(secs[TAG], len(quads))
    need(has_bit, 'symmetry section: the geometry section does not predict by it')
    return mirror_map(V, quads, seeds)
