#!/usr/bin/env python3
"""The properties section (0x0e, format 3.14) of a .qsp file, written from format-spec/qsp_format.md
("Properties section") alone, without reading the codec's C++: PLY vertex and face properties of any
scalar type (lists included) and the OBJ vertex weight, per output vertex and face.

decode_props() is what qsppoly.py calls; encode_props() writes a section from decoded properties (the
same fields, so that propsgen.py can build sections broken each way the text names); permute() moves
the values with an order section's vertices and faces.

A property is a dict: name (bytes; b'' for the OBJ vertex weight), face (bool), list (bool), type
(0..7, TYPES), count_type (0..5 for a list, else None), wide (flags bit 2), values (one per element: an
int, or a float's binary64 bits as an int, or a list of those for a list property). A float value is
kept as binary64 bits so that NaN payloads and -0 compare exactly; a binary32 value (bit 2 clear) is
widened to binary64 exactly (NaN: its payload shifted up, as an exact widening keeps it).

Points where the text leaves a choice are named by the constants below the imports.
"""
import struct

import qspgeo as g

need = g.need

TYPES = ('char', 'uchar', 'short', 'ushort', 'int', 'uint', 'float', 'double')
RANGE = {0: (-128, 127), 1: (0, 255), 2: (-32768, 32767), 3: (0, 65535), 4: (-2 ** 31, 2 ** 31 - 1),
         5: (0, 2 ** 32 - 1)}
FLOATS = (6, 7)
MAX_PROPERTIES = 65536         # "count P ... ≤ 65,536"
DIFFS_ACROSS_ELEMENTS = True   # "its difference d from the property's previous value (the first from
                               # 0)": for a list, taken as the previous value in the flat run of all
                               # its elements' values (the last of the element before for an element's
                               # first), not restarting at 0 for each element
STATS = {}


def seen(what):
    STATS[what] = STATS.get(what, 0) + 1


def widen(u):
    """Binary32 bits u as binary64 bits, exactly (NaN: sign, payload << 29)."""
    if u & 0x7F800000 == 0x7F800000 and u & 0x7FFFFF:
        return (u >> 31) << 63 | 0x7FF << 52 | (u & 0x7FFFFF) << 29
    return struct.unpack('<Q', struct.pack('<d', struct.unpack('<f', struct.pack('<I', u))[0]))[0]


def narrow(b):
    """Binary64 bits b as binary32 bits if binary32 holds the value exactly (NaN: if its payload's low
    29 bits are 0), else None."""
    if b >> 52 & 0x7FF == 0x7FF and b & ((1 << 52) - 1):
        if b & ((1 << 29) - 1):
            return None
        return (b >> 63) << 31 | 0x7F800000 | (b >> 29) & 0x7FFFFF
    y = struct.unpack('<d', struct.pack('<Q', b))[0]
    try:
        u = struct.unpack('<I', struct.pack('<f', y))[0]
    except OverflowError:
        return None
    return u if widen(u) == b else None


def as_float(b):
    return struct.unpack('<d', struct.pack('<Q', b))[0]


def decode_props(payload, V, F, minor):
    """The section's properties (see the module's doc) over V output vertices and F output faces, in
    the decoder's output order before any order section. Raises FormatError on anything the text
    refuses."""
    need(minor >= 14, 'section 0x0e (properties) is format 3.14\'s, and the file says it is 3.%d' % minor)
    P, at = g.read_varint(payload, 0)
    need(P >= 1, 'properties: count 0')
    need(3 * P <= len(payload) - at, 'properties: %d properties in %d bytes' % (P, len(payload) - at))
    need(P <= MAX_PROPERTIES, 'properties: %d properties, above the limit of %d' % (P, MAX_PROPERTIES))
    out = []
    face_seen = weight_seen = False
    names = set()  # (face, name) of the properties so far: "two properties of one element with the same name"
    for k in range(P):
        need(at + 2 <= len(payload), 'properties: property %d\'s flags and types past the section' % k)
        flags, types = payload[at], payload[at + 1]
        at += 2
        need(flags & 0xF8 == 0, 'properties: property %d\'s flags 0x%02x has a reserved bit (3 to 7) set' % (k, flags))
        face, is_list, wide = bool(flags & 1), bool(flags & 2), bool(flags & 4)
        vt, lt = types & 15, types >> 4
        need(vt <= 7, 'properties: property %d\'s value type %d (8 to 15 are invalid)' % (k, vt))
        if is_list:
            need(lt <= 5, 'properties: property %d\'s list length type %d is no integer type' % (k, lt))
        else:
            need(lt == 0, 'properties: scalar property %d with a list length type %d' % (k, lt))
        need(not wide or vt in FLOATS, 'properties: flags bit 2 (binary64) on property %d of integer type %s'
             % (k, TYPES[vt]))
        N, at = g.read_varint(payload, at)
        need(N <= len(payload) - at, 'properties: property %d\'s name of %d bytes past the section' % (k, N))
        name = bytes(payload[at:at + N])
        at += N
        need(all(0x21 <= c <= 0x7E for c in name), 'properties: name %r with a byte outside 0x21-0x7e' % name)
        if N == 0:
            need(not face and not is_list and vt in FLOATS,
                 'properties: an empty name on a property other than a scalar float or double vertex property')
            need(not weight_seen, 'properties: two vertex weights (empty names)')
            weight_seen = True
            seen('props: vertex weight')
        if face:
            face_seen = True
        else:
            need(not face_seen, 'properties: vertex property %r after a face property' % name)
        need(N == 0 or (face, name) not in names, 'properties: two %s properties named %r'
             % ('face' if face else 'vertex', name))
        names.add((face, name))
        n = F if face else V
        lengths = None
        if is_list:
            need(n <= len(payload) - at, 'properties: %d list lengths past the section' % n)
            lengths = []
            hi = RANGE[lt][1]
            for _ in range(n):
                L, at = g.read_varint(payload, at)
                need(L <= hi, 'properties: list length %d past %s\'s maximum' % (L, TYPES[lt]))
                lengths.append(L)
            m = sum(lengths)
            need(m < 1 << 32, 'properties: %d list values, 2^32 or more' % m)
            seen('props: list of %s' % TYPES[lt])
        else:
            m = n
        width = (8 if wide else 4) if vt in FLOATS else 1
        need(m * width <= len(payload) - at, 'properties: %d values of %r past the section' % (m, name))
        flat = []
        if vt in FLOATS:
            fmt = '<Q' if wide else '<I'
            for _ in range(m):
                u = struct.unpack_from(fmt, payload, at)[0]
                at += width
                flat.append(u if wide else widen(u))
            seen('props: %s%s' % (TYPES[vt], ' binary64' if wide else ''))
        else:
            lo, hi = RANGE[vt]
            prev = 0
            for _ in range(m):
                z, at = g.read_varint(payload, at)
                need(z < 1 << 34, 'properties: zigzag value %d, 2^34 or more' % z)
                v = prev + g.unzigzag(z)
                need(lo <= v <= hi, 'properties: value %d of %r outside %s\'s range' % (v, name, TYPES[vt]))
                flat.append(v)
                prev = v
            seen('props: %s' % TYPES[vt])
        if is_list:
            values, i = [], 0
            for L in lengths:
                values.append(flat[i:i + L])
                i += L
        else:
            values = flat
        out.append({'name': name, 'face': face, 'list': is_list, 'type': vt, 'count_type': lt if is_list else None,
                    'wide': wide, 'values': values})
    need(at == len(payload), 'properties: %d bytes after the last property' % (len(payload) - at))
    return out


def encode_props(props):
    """The section of these properties, as decode_props returns them (in that order)."""
    out = bytearray(g.varint(len(props)))
    for p in props:
        vt = p['type']
        out += bytes([int(p['face']) | 2 * int(p['list']) | 4 * int(p['wide']),
                      vt | (p['count_type'] << 4 if p['list'] else 0)])
        out += g.varint(len(p['name'])) + p['name']
        flat = []
        if p['list']:
            for v in p['values']:
                out += g.varint(len(v))
                flat += v
        else:
            flat = list(p['values'])
        if vt in FLOATS:
            for b in flat:
                out += struct.pack('<Q', b) if p['wide'] else struct.pack('<I', narrow(b))
        else:
            prev = 0
            for v in flat:
                out += g.varint(g.zigzag(v - prev))
                prev = v
    return bytes(out)


def permute(props, cv, of):
    """The properties moved by an order section: original vertex j has canonical vertex cv[j]'s values,
    original face f canonical face of[f][0]'s."""
    for p in props:
        p['values'] = [p['values'][c] for c, _ in of] if p['face'] else [p['values'][c] for c in cv]
    return props
