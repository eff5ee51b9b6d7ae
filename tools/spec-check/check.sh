#!/usr/bin/env bash
# Decodes geometry sections with tools/spec-check/qspgeo.py, written from format-spec/geometry_section.md
# and qsp_format.md alone (its coding orders and stencils too, from the topology section: qsplayout.py),
# and compares the stencils field for field and every coordinate bit for bit with the reference
# decoder's: every golden file (testdata/golden, and testdata/golden/tools with one file per combination
# of the geometry tools), and fresh encodes of testdata meshes, of a generated grid with float-bits
# axes (all three, or beside a decimal axis) and, when ../shared/meshes is there, of meshes that
# exercise chaining, repeats, shape transfers, layout order and trailing-zero coding; and two of them
# recoded under all 32 tools bytes. Each file of testdata/golden and golden/polygons, and fresh encodes
# of polygon meshes from polygen.py, are also decoded whole by qsppoly.py (format 3.1's polygons and
# comments sections too, from qsp_format.md alone) and compared with their .obj (faces, corner cycles,
# positions bit for bit when lossless, the leading comment block) and exactly with the reference
# decoder's output. Files with texture coordinates (format 3.2's section, and the order section, from
# the text too): each of testdata/golden/texcoords, fresh encodes of the textured testdata meshes, of
# bishop (triangles beside quads) from ../shared/meshes, and of polygon meshes given texture
# coordinates by texgen.py (seams, corners naming none or another vertex's value, values no corner
# names, float extremes, decimal values halfway between two grid integers), with and without
# --keep-order, and of texgen.py's smoothly bent grid (the corrections, grid lines, chords of
# hexagons), lossless and with --quantize-uv 12 and 7 (spot, fedora (the shapes) and bishop with 12
# too), are decoded whole by qsppoly.py and compared with their .obj (every corner's position and
# texture coordinate bits, rounded to the binary grid of --quantize-uv; index for index under
# --keep-order) and index for index with what `qsp decompress` writes. Files with face labels (format
# 3.3's section: o, g, usemtl, s and mtllib, from the text too; labelgen.py first checks that decoder,
# and qsp decompress, on streams breaking each rule the text names): each of testdata/golden/labels, and fresh encodes of
# polygon meshes (one with texture coordinates, one with --keep-order) given statements by labelgen.py,
# of MakeHuman's base mesh (groups, lossless, and with --keep-order) and OpenSubdiv's gregory_test2
# (materials, smoothing groups, an mtllib, a group no face takes), are decoded whole by qsppoly.py and
# compared with their .obj (each face's corner positions with its labels, as a multiset, or face by
# face for a file whose name holds keep_order; the names no face takes; the mtllib lines) and face by
# face with what `qsp decompress` writes. Files with OpenSubdiv tags (format 3.4's section, from the
# text too; tagsgen.py first checks that decoder, and qsp decompress, on sections breaking each rule the
# text names): each of testdata/golden/tags, and fresh encodes of OpenSubdiv's catmark_cube_creases1 and
# catmark_torus_creases0 (with and without --keep-order) and catmark_square_hedit0 (vertexedit: qsp
# keeps the original order for it), are decoded whole by qsppoly.py and compared tag for tag with their
# .obj (crease and corner vertices by position, hole faces by their corners, index for index for a file
# with an order section; floats by value) and with what `qsp decompress` writes. Files with normals
# (format 3.5's section, the texture coordinates section's payload with three components, from the text
# too; a normals section in a 3.4 file and one with other than three components are refused, by both
# decoders): each of testdata/golden/normals, and fresh encodes of pmp_suzanne and OpenSubdiv's
# catmark_chaikin0 (with and without --keep-order), are decoded whole by qsppoly.py and compared with
# their .obj (every corner's position and normal, float32 bits; index for index for a file with an
# order section; its texture coordinates, labels and tags too) and with what `qsp decompress` writes.
# Colours (format 3.8's section, from the text too: qspcolors.py): colorsgen.py --test writes coloured
# OBJ, OFF and PLY meshes (vertex and face colours, uchar, decimal, float32 and extreme components,
# --keep-order, --quantize-color) and checks that qsppoly.py decodes each file to its mesh's colours,
# that the section is byte for byte what the text's encoder choices give, that `qsp decompress` writes
# the same colours, and that broken sections are refused by both decoders; each of
# testdata/golden/colors is checked the same way against its mesh. Until qsp reads 3.8 (`qsp
# --version`) the files are --drop color files with the text's section put in, and qsp decompress is
# not asked.
# Interior positions (format 3.12's section: the polygons section's interior vertices coded in the
# geometry section after the layout's, with stencils from their fans, from the text too): every file
# above that has one (polygon goldens of 3.12, and every fresh polygon encode, polygen.py's meshes
# and bishop among them) is decoded whole by qsppoly.py and compared with its .obj (positions bit for
# bit when lossless) and index for index with what `qsp decompress` writes (dump_stencils reads a
# polygon file's geometry as its quad submesh's alone, which such a file's is not); and both decoders
# must refuse that section broken each way the text names (in a 3.11 file, a wrong count, bytes after
# the count or after the polygons section's stream, the section beside no polygons section).
# Properties (format 3.14's section, from the text too: qspprops.py, propsgen.py): each golden file of
# testdata/golden/properties, and fresh encodes (default and --keep-order) of propsgen.py --make's
# meshes (PLY vertex properties of every type and face lists with each count type, floats of more
# digits than binary32, a triangle beside quads, OBJ vertex weights), are decoded whole by qsppoly.py
# and every vertex's and face's property values compared with their mesh's and with what `qsp
# decompress` writes (a PLY, or an OBJ for a weight); both decoders must read valid rewrites of the section (binary64 floats, NaN and
# infinities, every printable name byte, an added weight) to the same values and refuse the section
# broken each way the text names (in a 3.13 file, reserved bits, invalid types, bad names, misplaced or
# repeated empty names, a vertex property after a face property, list lengths and values outside their
# types' ranges, bytes after the last property, ...).
# Polygon goldens of earlier versions (testdata/golden/v3.*/polygons) are checked as
# testdata/golden/polygons' are, against the mesh of today's golden of the same name.
# Coded comments (format 3.16's section, from the text too): the goldens holding it (grid_3x2_comments,
# grid_3x2_licence_comments) and the fresh encodes with a leading block (mh_fedora's licence among them)
# are decoded whole by qsppoly.py and their lines compared with the .obj's leading block and with the
# reference decoder's; both decoders must refuse the section broken each way the text names (in a 3.15
# file, beside a comments section, its stream cut or lengthened, a text length past its stream or past
# 2^20, a text of 2^16 + 1 lines), and accept a fresh encode of a block of 2^16 lines (the most the
# section holds; one more line goes to the plain comments section); the comment goldens of 3.15 (testdata/golden/v3.15, plain lines) are checked against today's mesh.
# Mirror prediction (format 3.17: the symmetry section and geometry tools bit 5, from the text too:
# qspmirror.py): every fresh encode above that the reference encoder mirrors (fedora, spot, pawn, xord)
# goes through qspgeo.py and qsppoly.py with the mirror sources the text gives, the mirrored fedora and
# xord are recoded under all 64 tools bytes, and both decoders must refuse the symmetry section broken
# each way the text names.
# Texture coordinates from their mirror images (format 3.18: the texture coordinates section's flag bit
# 5, from the text too): fresh --best encodes of the fedora (quantized, with and without --keep-order,
# lossless, and float bits) and of blub, and the golden testdata/golden/mirror/hull_uv12, must be 3.18
# files with flag bit 5 and are decoded whole by qsppoly.py against their mesh and what `qsp decompress`
# writes; both decoders must refuse flag bit 5 broken each way the text names, and qsppoly.py the
# must-fail files testdata/invalid/qsp_texcoords_mirror_*.
# Usage: check.sh QSP DUMP_STENCILS [PYTHON3]   (ctest runs it: "spec_decoder")
set -euo pipefail
qsp=$1 dump=$2 python=${3:-python3}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
files=("$root"/testdata/golden/*.qsp "$root"/testdata/golden/polygons/*.qsp "$root"/testdata/golden/tools/*.qsp)
declare -A obj_of=()  # the files qsppoly.py decodes whole, and the mesh each was made from
for f in "$root"/testdata/golden/mirror/*.qsp; do  # mirror prediction (3.17), decoded whole too
  [[ -f $f ]] || continue
  grep -q '^vt ' "${f%.qsp}.obj" && continue  # (with texture coordinates: below, whole, as tex_of's are)
  files+=("$f")
  obj_of[$f]=${f%.qsp}.obj
done
for f in "$root"/testdata/golden/v3.*/polygons/*.qsp; do  # polygon goldens of earlier versions
  [[ -f $f ]] || continue
  files+=("$f")
  name=$(basename "${f%.qsp}")
  obj_of[$f]=$root/testdata/golden/polygons/$name.obj  # the mesh today's golden of that name is made from
done
for f in "$root"/testdata/golden/v3.15/*.qsp; do  # comment goldens of 3.15 (plain lines), against today's mesh
  [[ -f $f ]] || continue
  files+=("$f")
  obj_of[$f]=$root/testdata/golden/$(basename "${f%.qsp}").obj
done
declare -A tex_of=()  # the files with texture coordinates, and the mesh each was made from
for f in "$root"/testdata/golden/texcoords/*.qsp; do tex_of[$f]=${f%.qsp}.obj; done
for f in "$root"/testdata/golden/v3.*/texcoords/*.qsp; do  # earlier versions, against today's mesh
  [[ -f $f ]] && tex_of[$f]=$root/testdata/golden/texcoords/$(basename "${f%.qsp}").obj
done
for f in "$root"/testdata/golden/mirror/*.qsp; do  # mirrored texture coordinates (3.18), whole against
  [[ -f $f ]] && grep -q '^vt ' "${f%.qsp}.obj" && tex_of[$f]=${f%.qsp}.obj  # the mesh and qsp decompress
done
for f in "$root"/testdata/golden/*.qsp "$root"/testdata/golden/polygons/*.qsp; do obj_of[$f]=${f%.qsp}.obj; done
declare -A lab_of=()  # the files with face labels, and the mesh each was made from
for f in "$root"/testdata/golden/labels/*.qsp; do [[ -f $f ]] && lab_of[$f]=${f%.qsp}.obj; done
for f in "$root"/testdata/golden/v3.*/labels/*.qsp; do  # earlier versions, against today's mesh
  [[ -f $f ]] && lab_of[$f]=$root/testdata/golden/labels/$(basename "${f%.qsp}").obj
done
# The statement order golden (3.11) has face labels too; its optional section is one a decoder may skip.
for f in "$root"/testdata/golden/statements/*.qsp; do [[ -f $f ]] && lab_of[$f]=${f%.qsp}.obj; done
declare -A tag_of=() tag_exact=()  # the files with subdivision tags, the mesh each was made from, and
for f in "$root"/testdata/golden/tags/*.qsp; do  # those with an order section (compared index for index)
  [[ -f $f ]] || continue
  tag_of[$f]=${f%.qsp}.obj
  [[ $(basename "$f") == *keep_order* ]] && tag_exact[$f]=1
done
for f in "$root"/testdata/golden/v3.*/tags/*.qsp; do  # earlier versions, against today's mesh
  [[ -f $f ]] || continue
  tag_of[$f]=$root/testdata/golden/tags/$(basename "${f%.qsp}").obj
  [[ $(basename "$f") == *keep_order* ]] && tag_exact[$f]=1
done
declare -A nrm_of=() nrm_exact=()  # the files with normals, the mesh each was made from, and those
for f in "$root"/testdata/golden/normals/*.qsp; do  # with an order section (compared index for index)
  [[ -f $f ]] || continue
  nrm_of[$f]=${f%.qsp}.obj
  [[ $(basename "$f") == *keep_order* ]] && nrm_exact[$f]=1
done
for f in "$root"/testdata/golden/v3.*/normals/*.qsp; do  # earlier versions, against today's mesh
  [[ -f $f ]] || continue
  nrm_of[$f]=$root/testdata/golden/normals/$(basename "${f%.qsp}").obj
  [[ $(basename "$f") == *keep_order* ]] && nrm_exact[$f]=1
done
# The normals section's own refusals, on a file without a symmetry section where there is one (3.16's
# copy), so that each broken file is refused for its normals alone.
cube_normals=$root/testdata/golden/normals/cube_normals.qsp
[[ -f $root/testdata/golden/v3.16/normals/cube_normals.qsp ]] && cube_normals=$root/testdata/golden/v3.16/normals/cube_normals.qsp
if [[ -f $cube_normals ]]; then
  "$python" - "$here" "$cube_normals" "$qsp" "$work" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
import qsppoly as poly
path, qsp, work = sys.argv[2:]
data = open(path, 'rb').read()
secs = g.sections(data)
cases = [('the file itself', data, True),
         ('a normals section in a 3.4 file', g.container(data[:9] + bytes([4]) + data[10:11], secs), False)]
for K in (0, 1, 2):
    sec = bytes([secs[0x09][0] & ~3 | K]) + secs[0x09][1:]
    cases.append(('normals with K = %d' % K, g.container(data, {**secs, 0x09: sec}), False))
if secs[0x09][0] & 0x20:  # 3.10's normals from the faces, in a file that says it is 3.9; bit 7 reserved
    cases.append(('normals from the faces in a 3.9 file', g.container(data[:9] + bytes([9]) + data[10:11], secs), False))
cases.append(('normals flag bit 7', g.container(data, {**secs, 0x09: bytes([secs[0x09][0] | 0x80]) + secs[0x09][1:]}), False))
failed = poly.refusals(cases, qsp, '%s/normals_case.qsp' % work)
for x in failed:
    print(x, file=sys.stderr)
sys.exit(1 if failed else 0)
PY
    { echo "normals sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
fi
if [[ -f $root/testdata/golden/grid_3x2_licence_comments.qsp ]]; then  # the coded comments section's refusals
  "$python" - "$here" "$root/testdata/golden/grid_3x2_licence_comments.qsp" "$qsp" "$work" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
import qsppoly as poly
import os
import subprocess
path, qsp, work = sys.argv[2:]
many = os.path.join(os.path.dirname(os.path.dirname(path)), 'invalid', 'qsp_coded_comments_too_many_lines.qsp')
data = open(path, 'rb').read()
secs = g.sections(data)
coded = secs[0x85]
rest = {t: p for t, p in secs.items() if t != 0x85}
cases = [('the file itself', data, True),
         ('a coded comments section in a 3.15 file', g.container(data[:9] + bytes([15]) + data[10:11], secs), False),
         ('beside a comments section', g.container(data, {**secs, 0x81: bytes([1, 1]) + b'x'}), False),
         ('its stream cut by 3 bytes', g.container(data, {**rest, 0x85: coded[:-3]}), False),
         ('a byte after its stream', g.container(data, {**rest, 0x85: coded + bytes([1])}), False),
         ('a text length past its stream', g.container(data, {**rest, 0x85: g.varint(1024 * (len(coded) - 2 + 8) + 1) +
                                                               coded[2:]}), False),
         ('a text length past 2^20', g.container(data, {**rest, 0x85: g.varint((1 << 20) + 1) + coded[2:] +
                                                         bytes(1100)}), False),
         ('a text of 2^16 + 1 lines', open(many, 'rb').read(), False)]
# A block of 2^16 lines (empty comments) and one of 2^16 + 1, compressed: the coded section holds the
# first, the plain comments section the second.
for n, tag in ((1 << 16, 0x85), ((1 << 16) + 1, 0x81)):
    obj = '%s/coded_comments_%d.obj' % (work, n)
    open(obj, 'w').write('#\n' * n + 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n')
    subprocess.run([qsp, 'compress', '-f', '-q', obj, obj + '.qsp'], check=True, capture_output=True)
    b = open(obj + '.qsp', 'rb').read()
    if tag not in g.sections(b) or poly.decode_file(b)[2] != [b''] * n:
        print('%d comment lines are not kept in section 0x%02x' % (n, tag), file=sys.stderr)
        sys.exit(1)
    cases.append(('%d comment lines' % n, b, True))
failed = poly.refusals(cases, qsp, '%s/coded_comments_case.qsp' % work)
for x in failed:
    print(x, file=sys.stderr)
sys.exit(1 if failed else 0)
PY
    { echo "coded comments sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
fi
"$python" "$here/labelgen.py" --test "$qsp" >/dev/null ||
  { echo "face labels streams from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
"$python" "$here/tagsgen.py" "$qsp" >/dev/null ||
  { echo "subdivision tags sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
encode() {  # encode NAME MESH [OPTIONS...]: a fresh file to check
  local name=$1 mesh=$2
  shift 2
  [[ -f $mesh ]] || return 0
  "$qsp" compress -f --positions-only "$@" "$mesh" "$work/$name.qsp" >/dev/null
  files+=("$work/$name.qsp")
}
bumpy() {  # bumpy OUT.obj MODE: a 16x16 grid whose y, z are not short decimals, so float bits;
           # x too for MODE float, x on a decimal grid (integers) for MODE mixed
  "$python" - "$@" <<'PY'
import math, random, struct, sys
out, mode = sys.argv[1], sys.argv[2]
random.seed(7)
n = 16
f32 = lambda x: struct.unpack('<f', struct.pack('<f', x))[0]
with open(out, 'w') as o:
    for j in range(n):
        for i in range(n):
            x = '%d' % i if mode == 'mixed' else '%.9g' % f32(i * 0.731 + 0.01 * math.sin(j))
            y = f32(j * 0.677 + 0.013 * math.cos(i) + 1e-3 * random.random())
            z = f32(0.3 * math.sin(i * 0.4) * math.cos(j * 0.3) + 1e-3 * random.random())
            o.write('v %s %.9g %.9g\n' % (x, y, z))
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i + 1
            o.write('f %d %d %d %d\n' % (a, a + 1, a + n + 1, a + n))
PY
}
for seed in 1 2 3; do  # polygon meshes (3.1 files), lossless and quantized
  "$python" "$here/polygen.py" "$work/polygons_$seed.obj" $seed
  encode polygons_$seed "$work/polygons_$seed.obj"
  obj_of[$work/polygons_$seed.qsp]=$work/polygons_$seed.obj
done
encode polygons_1_q12 "$work/polygons_1.obj" --quantize 12
obj_of[$work/polygons_1_q12.qsp]=$work/polygons_1.obj
encode polygons_3_keep_order "$work/polygons_3.obj" --keep-order   # the order section over a polygon mesh
obj_of[$work/polygons_3_keep_order.qsp]=$work/polygons_3.obj
# Small polygon meshes with interior vertices (3.12): a quad with triangles beside it and a fan round
# a pole, one coordinate of the fan off its decimal grid (an exception at an interior coding position,
# past V; patch order), and quantized (layout order at --best); and a mesh of triangles only (no
# layout vertex at all).
cat >"$work/quad_fan.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0.5 0.1
v -1 0.5 0.2
v -0.5 1.5 0.3
v -0.5 -0.7 0.1
v -1.6 0.6 0.40000004
f 1 2 3 4
f 2 5 3
f 4 6 1
f 6 4 7
f 9 6 7
f 9 8 6
f 8 1 6
OBJ
cat >"$work/triangles.obj" <<'OBJ'
v 0 0 0
v 1 0 0
v 2 0 0.1
v 0.5 1 0
v 1.5 1 0.2
v 2.5 1 0
v 1 2 0.3
v 2 2 0
v 1.5 3 0.1
f 1 2 4
f 2 5 4
f 2 3 5
f 3 6 5
f 4 5 7
f 5 8 7
f 5 6 8
f 7 8 9
OBJ
for t in "quad_fan quad_fan --float32" "quad_fan_q14_best quad_fan --quantize 14 --best" "triangles triangles" \
         "triangles_q14_best triangles -q --quantize 14 --best"; do
  read -r name mesh opts <<<"$t"
  encode "$name" "$work/$mesh.obj" $opts
  obj_of[$work/$name.qsp]=$work/$mesh.obj
done
# The interior positions section's own refusals (3.12), by both decoders, on polygons_1 (cube_4 for
# the section beside no polygons section).
"$python" - "$here" "$work/polygons_1.qsp" "$root/testdata/golden/cube_4.qsp" "$qsp" "$work" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
import qsppoly as poly
path, quad, qsp, work = sys.argv[2:]
data = open(path, 'rb').read()
secs = g.sections(data)
if 0x0c not in secs:
    print('spec decoder: %s has no interior positions section (0x0c)' % path, file=sys.stderr)
    sys.exit(1)
N, _ = g.read_varint(secs[0x0c], 0)
minor = lambda b, m: b[:9] + bytes([m]) + b[10:11]
without = {t: p for t, p in secs.items() if t != 0x0c}
cases = [('the file itself', data, True),
         ('an interior positions section in a 3.11 file', g.container(minor(data, 11), secs), False),
         ('the geometry of a 3.12 file without its interior positions section', g.container(minor(data, 11), without), False),
         ('a byte after the polygons section\'s stream', g.container(data, {**secs, 0x05: secs[0x05] + b'\0'}), False),
         ('a byte after the interior position count', g.container(data, {**secs, 0x0c: secs[0x0c] + b'\0'}), False),
         ('an empty interior positions section', g.container(data, {**secs, 0x0c: b''}), False)]
for n in (0, N - 1, N + 1):
    if n >= 0 and n != N:
        cases.append(('interior position count %d, not %d' % (n, N), g.container(data, {**secs, 0x0c: g.varint(n)}), False))
qdata = open(quad, 'rb').read()
cases.append(('an interior positions section beside no polygons section',
              g.container(minor(qdata, 12), {**g.sections(qdata), 0x0c: g.varint(1)}), False))
failed = poly.refusals(cases, qsp, '%s/interior_case.qsp' % work)
for x in failed:
    print(x, file=sys.stderr)
sys.exit(1 if failed else 0)
PY
  { echo "interior positions sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
# encode_kept KIND NAME MESH EXACT [OPTIONS...]: a fresh file to check as KIND (tex, lab, tag or nrm):
# KIND_of[FILE]=MESH, and KIND_exact[FILE]=1 (compared index for index) when EXACT is 1.
encode_kept() {
  local kind=$1 name=$2 mesh=$3 exact=$4
  shift 4
  [[ -f $mesh ]] || return 0
  if ! "$qsp" compress -f "$@" "$mesh" "$work/$name.qsp" >/dev/null 2>"$work/$name.err"; then
    cat "$work/$name.err" >&2  # (its notes on rounding and dropped data are not news)
    exit 1
  fi
  local -n of=${kind}_of
  of[$work/$name.qsp]=$mesh
  if [[ $exact == 1 ]]; then
    local -n exact_of=${kind}_exact
    exact_of[$work/$name.qsp]=1
  fi
  return 0
}
encode_tex() {  # encode_tex NAME MESH [OPTIONS...]: a fresh file with texture coordinates to check
  encode_kept tex "$1" "$2" 0 --drop normal,group,material,smoothing,tag,extra "${@:3}"
}
for t in "1 uv" "2 u" "3 uvw" "1 uh" "2 uv --keep-order" "3 uvw --keep-order"; do  # polygon meshes with texture coordinates
  read -r seed mode keep <<<"$t"
  name=tex_${seed}_$mode${keep:+_keep_order}
  "$python" "$here/texgen.py" "$work/polygons_$seed.obj" "$work/$name.obj" "$seed" "$mode"
  encode_tex "$name" "$work/$name.obj" --float32 $keep
done
encode_labels() {  # encode_labels NAME MESH [OPTIONS...]: a fresh file with face labels to check
  encode_kept lab "$1" "$2" 0 "${@:3}"
}
for t in "polygons_1" "polygons_2 --keep-order" "tex_1_uv --float32"; do  # labelgen.py's statements
  read -r mesh opts <<<"$t"                                                  # among their faces
  name=labels_$mesh${opts:+_${opts#--}}
  name=${name//-/_}
  "$python" "$here/labelgen.py" "$work/$mesh.obj" "$work/$name.obj" 1
  encode_labels "$name" "$work/$name.obj" $opts
done
"$python" "$here/texgen.py" - "$work/bent.obj" 1 bent  # smooth: the corrections and grid lines pay
encode_tex bent_uv "$work/bent.obj" --float32
encode_tex bent_uv12 "$work/bent.obj" --float32 --quantize-uv 12   # binary grids, with the corrections
encode_tex bent_uv7 "$work/bent.obj" --float32 --quantize-uv 7     # and without
encode_tex bent_uv12_keep_order "$work/bent.obj" --float32 --quantize-uv 12 --keep-order
encode_tex spot_uv "$root/testdata/keenan_spot_quadrangulated.obj"
encode_tex spot_uv12 "$root/testdata/keenan_spot_quadrangulated.obj" --quantize-uv 12  # (../shared's copy too)
encode_tex fedora_uv "$root/testdata/mh_fedora.obj"
encode_tex fedora_uv_keep_order "$root/testdata/mh_fedora.obj" --keep-order
encode_tex fedora_uv12 "$root/testdata/mh_fedora.obj" --quantize-uv 12   # charts that follow the surface
encode fedora "$root/testdata/mh_fedora.obj"                     # decimal grid, lossless
encode fedora_q14 "$root/testdata/mh_fedora.obj" --quantize 14
encode spot_q14 "$root/testdata/keenan_spot_quadrangulated.obj" --quantize 14
encode spot_q6 "$root/testdata/keenan_spot_quadrangulated.obj" --quantize 6
# Mirror prediction (format 3.17: the symmetry section and geometry tools bit 5, from the text too:
# qspmirror.py): the fresh encodes above of the fedora and spot are mirrored and go through qspgeo.py and
# qsppoly.py with the rest; both decoders must read the fedora's file with its seed given twice, and
# refuse its symmetry section broken each way the text names (in a 3.16 file, a seed count above F or
# above the bytes, a face or image out of range, axis 3, reserved bits, a byte after the seeds, the
# section without tools bit 5, bit 5 without the section, a seed mapping the wrong face or turn), and
# read two valid rewrites (the seed from the image's side; no seeds, the geometry coded again).
"$python" - "$here" "$work/fedora_q14.qsp" "$qsp" "$work" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
import qsppoly as poly
import qspmirror
path, qsp, work = sys.argv[2:]
data = open(path, 'rb').read()
secs = g.sections(data)
if 0x0f not in secs:
    print('spec decoder: %s has no symmetry section (0x0f)' % path, file=sys.stderr)
    sys.exit(1)
V, F, C, U = g.counts(secs[1])
seeds = qspmirror.parse_symmetry(secs[0x0f], F)
minor = lambda b, m: b[:9] + bytes([m]) + b[10:11]
def sym(ss, extra=b''):
    out = g.varint(len(ss))
    for f, im, r, axis in ss:
        out += g.varint(f) + g.varint(im) + bytes([r | axis << 2])
    return out + extra
def with_sym(payload):
    return g.container(data, {**secs, 0x0f: payload})
f0, g0, r0, a0 = seeds[0]
geo = secs[3]
cases = [('the file itself', data, True),
         ('its first seed given twice', with_sym(sym(seeds + seeds[:1])), True),
         ('a symmetry section in a 3.16 file', g.container(minor(data, 16), secs), False),
         ('a seed count above F', with_sym(g.varint(F + 1) + sym(seeds)[1:] * (F + 1)), False),
         ('a seed count above the bytes left / 3', with_sym(g.varint(1) + b'\0\0'), False),
         ('a seed face = F', with_sym(sym([(F, g0, r0, a0)] + seeds[1:])), False),
         ('a seed image = F', with_sym(sym([(f0, F, r0, a0)] + seeds[1:])), False),
         ('a seed of axis 3', with_sym(sym([(f0, g0, r0, 3)] + seeds[1:])), False),
         ('a seed byte with bit 4 set', with_sym(sym([(f0, g0, r0 | 16, a0)] + seeds[1:])), False),
         ('a byte after the seeds', with_sym(sym(seeds, b'\0')), False),
         ('a symmetry section beside a geometry section without tools bit 5',
          g.container(data, {**secs, 3: bytes([geo[0] & ~0x20]) + geo[1:]}), False),
         ('tools bit 5 without a symmetry section', g.container(data, {t: p for t, p in secs.items() if t != 0x0f}), False),
         ('tools bit 6', g.container(data, {**secs, 3: bytes([geo[0] | 0x40]) + geo[1:]}), False),
         ('a seed of another turn', with_sym(sym([(f0, g0, (r0 + 1) % 4, a0)] + seeds[1:])), False),
         ('a seed mapping its face to itself', with_sym(sym([(f0, f0, r0, a0)] + seeds[1:])), False)]
# Valid rewrites that decode to the same positions: the fedora's mirror is an involution, so its seed
# given from the image's side gives the same map; and no seeds at all, the geometry coded again (by the
# text's encoder) without mirror sources under the same tools byte.
import qsplayout as lay
coding, st = lay.stencils(secs[2], C, U, bool(geo[0] & g.LAYOUT_ORDER))
fb, info = g.decode_geometry(geo, V, st, mirror=g.file_mirror(data, secs, coding))
header = geo[:len(geo) - len(g.parse_header(geo, V)[-1])]
for what, b in (('its first seed given from the image\'s side', with_sym(sym([(g0, f0, r0, a0)] + seeds[1:]))),
                ('no seeds, the geometry coded again without mirror sources',
                 g.container(data, {**secs, 3: g.decode_geometry(header, V, st, target=info['values'], mirror=[]),
                                    0x0f: g.varint(0)}))):
    cases.append((what, b, True))
    if poly.decode_file(b)[0] != poly.decode_file(data)[0]:
        print('qsppoly.py decodes %s to other positions' % what, file=sys.stderr)
        sys.exit(1)
failed = poly.refusals(cases, qsp, '%s/symmetry_case.qsp' % work)
for x in failed:
    print(x, file=sys.stderr)
sys.exit(1 if failed else 0)
PY
  { echo "symmetry sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
# Texture coordinates predicted from their mirror images' (format 3.18: the texture coordinates
# section's flag bit 5, from the text too): the fedora at --best, quantized (with and without
# --keep-order), lossless (decimal grids) and with its texture coordinates scaled to binary32 prints
# (float bits beside a decimal grid), and blub (../shared) at --best below, are 3.18 files with flag bit
# 5, decoded whole by qsppoly.py against their mesh and what `qsp decompress` writes with the rest; both
# decoders must refuse flag bit 5 broken each way the text names (in a 3.17 file, a sign bit at K or at
# 7, without a symmetry section, beside a polygons section (a polygon file given an empty symmetry
# section and tools bit 5, which both read without flag bit 5), and reserved flag bit 6.
encode_tex fedora_mirror_uv12 "$root/testdata/mh_fedora.obj" --best --quantize 14 --quantize-uv 12
encode_tex fedora_mirror_uv12_keep_order "$root/testdata/mh_fedora.obj" --best --keep-order --quantize 14 \
  --quantize-uv 12
encode_tex fedora_mirror_uv "$root/testdata/mh_fedora.obj" --best
"$python" - "$root/testdata/mh_fedora.obj" "$work/fedora_float.obj" <<'PY'
import math, struct, sys
f32 = lambda x: struct.unpack('<f', struct.pack('<f', x))[0]
out = []
for line in open(sys.argv[1]):
    if line.startswith('vt '):   # u' = 1 - u and v' = v stay mirrored; 9 digits: float bits or 9 decimals
        u, v = map(float, line.split()[1:3])
        line = 'vt %.9g %.9g\n' % (f32(u * math.pi / 10), f32(v * math.pi / 10))
    out.append(line)
open(sys.argv[2], 'w').writelines(out)
PY
encode_tex fedora_mirror_float "$work/fedora_float.obj" --best
"$qsp" compress -f --quantize 14 --quantize-uv 12 "$work/tex_1_uv.obj" "$work/tex_1_uv_q14.qsp" >/dev/null
"$python" - "$here" "$work" "$qsp" <<'PY' ||
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
import qsppoly as poly
work, qsp = sys.argv[2:]
minor = lambda b, m: b[:9] + bytes([m]) + b[10:]
def modes_end(p):   # the offset after the K mode bytes: the signs byte with flag bit 5
    T, pos = g.read_varint(p, 1)
    U, pos = g.read_varint(p, pos)
    return pos + (p[0] & 3)
data = open('%s/fedora_mirror_uv12.qsp' % work, 'rb').read()
secs = g.sections(data)
tex = secs[6]
K, at = tex[0] & 3, modes_end(tex)
if not tex[0] & 0x20 or 0x0f not in secs:
    print('spec decoder: %s/fedora_mirror_uv12.qsp has no texture coordinates flag bit 5' % work, file=sys.stderr)
    sys.exit(1)
with_tex = lambda d, s, p: g.container(d, {**s, 6: p})
signs = lambda b: tex[:at] + bytes([b]) + tex[at + 1:]
poly_data = open('%s/tex_1_uv.qsp' % work, 'rb').read()   # a polygon mesh, no symmetry section
ps = g.sections(poly_data)
def bit5(p):   # flag bit 5 and a signs byte of 0
    e = modes_end(p)
    return bytes([p[0] | 0x20]) + p[1:e] + b'\0' + p[e:]
q14 = open('%s/tex_1_uv_q14.qsp' % work, 'rb').read()   # the same on integer axes
qs = g.sections(q14)
qs = {**qs, 3: bytes([qs[3][0] | 0x20]) + qs[3][1:], 0x0f: g.varint(0)}
cases = [('the file itself', data, True),
         ('flag bit 5 in a 3.17 file', g.container(minor(data, 17), secs), False),
         ('a sign bit at K', with_tex(data, secs, signs(tex[at] | 1 << K)), False),
         ('sign bit 7', with_tex(data, secs, signs(tex[at] | 0x80)), False),
         ('flag bit 6', with_tex(data, secs, bytes([tex[0] | 0x40]) + tex[1:]), False),
         ('flag bit 5 without a symmetry section', with_tex(minor(poly_data, 18), ps, bit5(ps[6])), False),
         ('a polygon file given an empty symmetry section and tools bit 5', g.container(minor(q14, 18), qs), True),
         ('flag bit 5 beside a polygons section', with_tex(minor(q14, 18), qs, bit5(qs[6])), False)]
failed = poly.refusals(cases, qsp, '%s/texcoords_bit5_case.qsp' % work)
for x in failed:
    print(x, file=sys.stderr)
sys.exit(1 if failed else 0)
PY
  { echo "texture coordinates flag bit 5 from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
# The must-fail files of the symmetry section and mirror prediction (testdata/invalid, which the
# reference refuses in its tests): the text refuses each too.
for f in "$root"/testdata/invalid/qsp_mirror_*.qsp "$root"/testdata/invalid/qsp_symmetry_*.qsp \
  "$root"/testdata/invalid/qsp_polygons_interior_mirror_bit.qsp "$root"/testdata/invalid/qsp_texcoords_mirror_*.qsp; do
  [[ -f $f ]] || continue
  if "$python" "$here/qsppoly.py" "$f" >/dev/null; then
    echo "spec decoder: qsppoly.py reads $f, which the reference refuses" >&2
    exit 1
  fi
done
bumpy "$work/bumpy_float.obj" float
encode bumpy_float "$work/bumpy_float.obj" --float32             # %.9g prints of float32: float bits only
bumpy "$work/bumpy_mixed.obj" mixed
encode bumpy_mixed "$work/bumpy_mixed.obj" --float32             # float bits beside a decimal axis
shared="${QSP_SHARED_DIR:-$root/../shared}/meshes"  # QSP_SHARED_DIR as the C++ tests read it
if [[ ! -f $shared/MANIFEST.tsv ]]; then
  if [[ ${CI:-} == true || ${QSP_REQUIRE_SHARED:-} == 1 ]]; then
    echo "spec decoder: $shared is missing, and this run requires it (CI=true or QSP_REQUIRE_SHARED=1)" >&2
    exit 1
  fi
  echo "spec decoder: $shared absent: its 21 real-mesh encodes are skipped"
fi
encode_tex bishop_uv "$shared/osd_catmark_bishop.obj"                       # triangles: a polygons section
encode_tex bishop_uv_keep_order "$shared/osd_catmark_bishop.obj" --keep-order
encode_tex bishop_uv12 "$shared/osd_catmark_bishop.obj" --quantize-uv 12
encode_labels mh_base_labels "$shared/mh_base.obj" --drop uv                 # 172 g statements
encode_labels mh_base_labels_keep_order "$shared/mh_base.obj" --drop uv --keep-order
encode_labels gregory_labels "$shared/osd_shapes/catmark_gregory_test2.obj" --drop normal
encode_tags() {  # encode_tags NAME MESH EXACT [OPTIONS...]: a fresh file with tags to check
  encode_kept tag "$1" "$2" "$3" --drop normal "${@:4}"
}
encode_tags cube_creases1_tags "$shared/osd_shapes/catmark_cube_creases1.obj" 0
encode_tags cube_creases1_tags_keep_order "$shared/osd_shapes/catmark_cube_creases1.obj" 1 --keep-order
encode_tags torus_creases0_tags "$shared/osd_shapes/catmark_torus_creases0.obj" 0
encode_tags torus_creases0_tags_keep_order "$shared/osd_shapes/catmark_torus_creases0.obj" 1 --keep-order
encode_tags square_hedit0_tags "$shared/osd_shapes/catmark_square_hedit0.obj" 1  # order kept for vertexedit
encode_normals() {  # encode_normals NAME MESH EXACT [OPTIONS...]: a fresh file with normals to check
  encode_kept nrm "$@"
}
encode_normals suzanne_normals "$shared/pmp_suzanne.obj" 0                   # o, s, usemtl, mtllib too
encode_normals suzanne_normals_keep_order "$shared/pmp_suzanne.obj" 1 --keep-order
encode_normals chaikin0_normals "$shared/osd_shapes/catmark_chaikin0.obj" 0  # vt and crease tags too
encode_normals chaikin0_normals_keep_order "$shared/osd_shapes/catmark_chaikin0.obj" 1 --keep-order
encode_normals suzanne_normals_qn10 "$shared/pmp_suzanne.obj" 0 --quantize-normal 10  # octahedral (3.10)
encode_normals lefthanded_normals "$shared/osd_catmark_lefthanded.obj" 0     # from the faces, -0 on grids
encode_normals lefthanded_normals_qn12 "$shared/osd_catmark_lefthanded.obj" 0 --quantize-normal 12
encode_tex blub_mirror_uv12 "$shared/keenan_blub_quadrangulated.obj" --best --quantize 14 --quantize-uv 12
encode_tex blub_mirror_uv12_keep_order "$shared/keenan_blub_quadrangulated.obj" --best --keep-order --quantize 14 \
  --quantize-uv 12
for f in "$work"/*_mirror_*.qsp; do  # (3.18: flag bit 5, where the encoder found it smaller)
  if ! "$qsp" stats "$f" | grep -q "format 3\.18,"; then
    echo "spec decoder: $f is not a 3.18 file, as texture coordinates predicted from their mirror images make it" >&2
    exit 1
  fi
done
encode gargoyle_q14 "$shared/quadriflow_gargoyle.obj" --quantize 14  # normal chaining, distorted cells
encode gargoyle_q14_best "$shared/quadriflow_gargoyle.obj" --quantize 14 --best  # and the costly tools
encode horse "$shared/igl_horse_quad.obj" --best
encode pawn "$shared/osd_catmark_pawn.obj" --best                    # value repeats, shape transfers
encode xord "$shared/osd_catmark_xord_interior.obj"                  # exceptions, trailing zeros
encode xord_q14 "$shared/osd_catmark_xord_interior.obj" --quantize 14
# The encoder writes only the tool combinations its levels try; qspgeo.py --recode writes a file again
# under each of the 32 tools bytes (same header and values, its own encoder from the text), and the
# reference must decode each to the original's positions: lossless decimal axes with exceptions and
# trailing zeros (xord), float bits beside a decimal axis (bumpy_mixed), and a mirrored file (the
# fedora at 14 bits: 64 tools bytes, mirror prediction with every other tool and both coding orders).
declare -A original=()
recode() {  # recode NAME: NAME.qsp under every tools byte
  local f=$work/$1.qsp
  [[ -f $f ]] || return 0
  mkdir -p "$work/recode"
  "$dump" "$f" "$work/recode/$1"
  while read -r g; do
    files+=("$g")
    original[$g]=$work/recode/$1.pos
  done < <("$python" "$here/qspgeo.py" --recode "$f" "$work/recode")
}
recode xord
recode bumpy_mixed
recode fedora_q14
# Exact positions (format 3.6's section, from the text too: qspexact.py). exactgen.py first checks
# that decoder, and qsp decompress once qsp says it reads 3.6, on sections put into golden files (valid
# ones, decoded to the values they were made from, and ones breaking each rule the text names). Then
# each of testdata/golden/exact, and meshes whose coordinates binary32 does not hold (exactgen.py
# --digits: ten and seventeen significant digits, short decimals, -0) made from polygen.py's meshes
# (.obj, .off and binary64 .ply, one with --keep-order), mh_fedora (texture coordinates, comments),
# the bumpy grid and exactgen.py --tricky's texts (1.0000000596046448, whose binary32 through its
# binary64 is not the one read directly; 2^62 written out; zeros beyond binary64's digits; a value
# above FLT_MAX), are decoded whole by qsppoly.py: every vertex's binary64 position against the value
# its text denotes (index for index with an order section; the section byte for byte with the text's
# encoder choices) and against what `qsp decompress` writes (the shortest text that reads back to
# each). Until qsp reads 3.6 those files are their --float32 files with exactgen.py's section put in
# (--put), and qsp decompress is not asked.
reads36=0
if "$qsp" --version | grep -Eq 'reads 3\.0 to 3\.([6-9]|[1-9][0-9])'; then
  reads36=1
elif [[ -f $root/src/codec_exact.cpp ]]; then
  echo "spec decoder: src/codec_exact.cpp is there but \`qsp --version\` does not say it reads format 3.6" >&2
  exit 1
fi
"$python" "$here/exactgen.py" --test "$qsp" >/dev/null ||
  { echo "exact positions sections from the text: the spec decoder or qsp decompress disagrees" >&2; exit 1; }
# Colours (format 3.8's section, from the text too: qspcolors.py, colorsgen.py).
if ! "$qsp" --version | grep -Eq 'reads 3\.0 to 3\.([8-9]|[1-9][0-9])' && [[ -f $root/src/codec_colors.cpp ]]; then
  echo "spec decoder: src/codec_colors.cpp is there but \`qsp --version\` does not say it reads format 3.8" >&2
  exit 1
fi
"$python" "$here/colorsgen.py" --test "$qsp" >/dev/null ||
  { echo "colours sections from the text: the spec decoder, the text's encoder or qsp disagrees" \
         "(colorsgen.py --test $qsp says where)" >&2; exit 1; }
colors_checked=0
for f in "$root"/testdata/golden/colors/*.qsp; do
  [[ -f $f ]] || continue
  mesh=
  for m in "${f%.qsp}.obj" "${f%.qsp}.off" "${f%.qsp}.ply"; do [[ -f $m ]] && mesh=$m; done
  [[ -n $mesh ]] || { echo "spec decoder: no mesh beside $f" >&2; exit 1; }
  "$python" "$here/colorsgen.py" --check "$f" "$mesh" "$qsp" >/dev/null ||
    { echo "spec decoder's colours disagree: $f (colorsgen.py --check $f $mesh $qsp says where)" >&2; exit 1; }
  colors_checked=$((colors_checked + 1))
done
declare -A exa_of=() exa_exact=()  # the files with exact positions, the mesh each was made from, and
for f in "$root"/testdata/golden/exact/*.qsp; do  # those with an order section (compared index for index)
  [[ -f $f ]] || continue
  for m in "${f%.qsp}.obj" "${f%.qsp}.off" "${f%.qsp}.ply"; do [[ -f $m ]] && exa_of[$f]=$m; done
  [[ $(basename "$f") == *keep_order* ]] && exa_exact[$f]=1
  files+=("$f")
done
encode_exact() {  # encode_exact NAME SOURCE.obj MESH.obj|.off|.ply [OPTIONS...]: SOURCE, more digits
  local name=$1 src=$2 mesh=$3
  shift 3
  "$python" "$here/exactgen.py" --digits "$src" "$mesh" "${#files[@]}"
  if ((reads36)); then
    "$qsp" compress -f -q "$@" "$mesh" "$work/$name.qsp"
  else
    "$qsp" compress -f -q --float32 "$@" "$mesh" "$work/$name.f32.qsp" &&
      "$python" "$here/exactgen.py" --put "$work/$name.f32.qsp" "$mesh" "$work/$name.qsp"
  fi || { echo "spec decoder: no exact positions file $name.qsp" >&2; exit 1; }
  exa_of[$work/$name.qsp]=$mesh
  [[ " $* " == *" --keep-order "* ]] && exa_exact[$work/$name.qsp]=1
  files+=("$work/$name.qsp")
}
encode_exact digits_polygons_1 "$work/polygons_1.obj" "$work/digits_polygons_1.obj"
encode_exact digits_polygons_2_off "$work/polygons_2.obj" "$work/digits_polygons_2.off"
encode_exact digits_polygons_1_ply "$work/polygons_1.obj" "$work/digits_polygons_1.ply"  # binary64 data
encode_exact digits_polygons_3_keep_order "$work/polygons_3.obj" "$work/digits_polygons_3.obj" --keep-order
encode_exact digits_bumpy "$work/bumpy_float.obj" "$work/digits_bumpy.obj"
encode_exact digits_fedora "$root/testdata/mh_fedora.obj" "$work/digits_fedora.obj"  # uv, comments
if ((reads36)); then  # texts whose binary32 must come from their binary64 (--put has no such f)
  "$python" "$here/exactgen.py" --tricky "$work/tricky.obj"
  "$qsp" compress -f -q "$work/tricky.obj" "$work/tricky.qsp" ||
    { echo "spec decoder: qsp compress refuses exactgen.py --tricky's mesh (each f must be the" \
           "binary32 nearest the value's binary64)" >&2; exit 1; }
  exa_of[$work/tricky.qsp]=$work/tricky.obj
  files+=("$work/tricky.qsp")
fi
# Exact values (format 3.13's section, from the text too: qspvalues.py, valuesgen.py): texture
# coordinates, normals and vertex and face colours binary32 does not hold. Every golden file under
# testdata/golden that has the section, and fresh encodes of valuesgen.py --make's meshes (2-, 3- and
# 1-component texture coordinates and normals of 10 to 17 significant digits beside binary32 values,
# short decimals and -0; OBJ vertex colours of 12 digits, rgb and rgba; triangles with all three; OFF
# vertex and face colours; binary64 PLY colours; a mesh of short decimals that needs no section), with
# and without --keep-order, are decoded whole by qsppoly.py and their values compared as binary64 with
# their mesh's texts (index for index for a file whose name holds keep_order, else as multisets and
# corner by corner; the section byte for byte with the text's encoder choices) and index for index with
# what `qsp decompress` writes. Both decoders must read each golden file's section and three fresh ones
# rewritten in other modes and widths to the same values, and refuse them broken each way the text
# names (valuesgen.py --test: kinds 0, a reserved kind bit, a kind whose array the mesh does not have,
# a block length past the section, a block not its array's size, bytes after the last block, a value
# not rounding to its binary32, the section in a 3.12 file, ...).
declare -A val_of=() val_only=()  # the files with exact values (or meant to test them), and their mesh
reads313=0
"$qsp" --version | grep -Eq 'reads 3\.0 to 3\.(1[3-9]|[2-9][0-9])' && reads313=1
while read -r f; do
  mesh=
  for m in "${f%.qsp}.obj" "${f%.qsp}.off" "${f%.qsp}.ply"; do [[ -f $m ]] && mesh=$m; done
  [[ -n $mesh ]] || { echo "spec decoder: no mesh beside $f" >&2; exit 1; }
  val_of[$f]=$mesh
done < <("$python" - "$here" "$root/testdata/golden" <<'PY'
import os, sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
for d, _, names in sorted(os.walk(sys.argv[2])):
    for n in sorted(names):
        if n.endswith('.qsp') and 0x0d in g.sections(open(os.path.join(d, n), 'rb').read()):
            print(os.path.join(d, n))
PY
)
values_tests=("${!val_of[@]}")  # valuesgen.py --test: every golden file with the section, three fresh
if ((reads313)); then
  mkdir -p "$work/values" "$work/values_test"
  while IFS=$'\t' read -r name mesh opts; do
    "$qsp" compress -f -q $opts "$mesh" "$work/values/$name.qsp" ||
      { echo "spec decoder: qsp compress refuses valuesgen.py's $mesh ($opts)" >&2; exit 1; }
    val_of[$work/values/$name.qsp]=$mesh
    val_only[$work/values/$name.qsp]=1
    case $name in values_triangles | values_off_3_keep_order | values_ply) values_tests+=("$work/values/$name.qsp") ;; esac
  done < <("$python" "$here/valuesgen.py" --make "$work/values")
  for f in "${values_tests[@]}"; do
    "$python" "$here/valuesgen.py" --test "$f" "$qsp" "$work/values_test" ||
      { echo "exact values sections from the text: the spec decoder or qsp decompress disagrees on $f" >&2; exit 1; }
  done
else
  echo "spec decoder: qsp does not say it reads format 3.13: its exact values encodes are skipped"
  ((${#val_of[@]} == 0)) || { echo "spec decoder: golden files with exact values, and qsp does not read 3.13" >&2; exit 1; }
fi
# Properties (format 3.14's section, from the text too: qspprops.py, propsgen.py): each golden file of
# testdata/golden/properties, and fresh encodes (default and --keep-order) of propsgen.py --make's
# meshes (a binary PLY with vertex properties of every type and face lists with each count type; an
# ASCII PLY with a triangle, floats of more digits than binary32 and lists of floats; an OBJ with
# vertex weights), are decoded whole by qsppoly.py and each vertex's and face's property values
# compared with their mesh's (names, types, header order, values exactly, flags bit 2 on a float
# property exactly where a value is not binary32's) and with the PLY (or, for a weight, the OBJ) `qsp
# decompress` writes; both decoders must read
# valid rewrites of the section to the same values and refuse it broken each way the text names
# (propsgen.py --test).
props_checked=0
if "$qsp" --version | grep -Eq 'reads 3\.0 to 3\.(1[4-9]|[2-9][0-9])'; then
  mkdir -p "$work/props" "$work/props_test"
  props_files=()
  declare -A props_mesh=()  # the mesh each was made from
  for f in "$root"/testdata/golden/properties/*.qsp; do
    [[ -f $f ]] || continue
    props_files+=("$f")
    for m in "${f%.qsp}.ply" "${f%.qsp}.obj"; do [[ -f $m ]] && props_mesh[$f]=$m; done
  done
  while IFS=$'\t' read -r name mesh; do
    for opts in "" --keep-order; do
      out=$work/props/$name${opts:+_keep_order}.qsp
      "$qsp" compress -f -q $opts "$mesh" "$out" ||
        { echo "spec decoder: qsp compress refuses propsgen.py's $mesh ($opts)" >&2; exit 1; }
      props_files+=("$out")
      props_mesh[$out]=$mesh
    done
  done < <("$python" "$here/propsgen.py" --make "$work/props")
  for f in "${props_files[@]}"; do
    "$python" "$here/propsgen.py" --test "$f" "$qsp" "$work/props_test" ${props_mesh[$f]:+"${props_mesh[$f]}"} ||
      { echo "properties sections from the text: the spec decoder or qsp decompress disagrees on $f" \
             "(propsgen.py --test $f $qsp DIR says where)" >&2; exit 1; }
    props_checked=$((props_checked + 1))
  done
else
  echo "spec decoder: qsp does not say it reads format 3.14: its properties are skipped"
  if compgen -G "$root/testdata/golden/properties/*.qsp" >/dev/null; then
    echo "spec decoder: golden files with properties, and qsp does not read 3.14" >&2
    exit 1
  fi
fi
valued() {  # valued FILE MESH: binary64 texture coordinates, normals and colours against MESH's texts
  local f=$1 out exact=() whole=() ext=obj  # and what `qsp decompress` writes
  [[ $2 == *.off || $2 == *.ply ]] && ext=off
  out="$work/$(basename "$f" .qsp)_values_$BASHPID.$ext"
  [[ $(basename "$f") == *keep_order* ]] && exact=(--exact)
  [[ $ext == obj ]] && whole=(--obj "$2" --tex-obj "$2" --normals-obj "$2" --decompressed "$out" --normals-decompressed "$out")
  "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
    "$python" "$here/qsppoly.py" "$f" "${whole[@]}" --values-obj "$2" "${exact[@]}" --values-decompressed "$out"
}
exacted() {  # exacted FILE MESH: binary64 positions against MESH's text and what `qsp decompress` writes
  local f=$1 out exact=() obj=()
  out="$work/$(basename "$f" .qsp)_$BASHPID.obj"
  [[ -n ${exa_exact[$f]:-} ]] && exact=(--exact)
  [[ $2 == *.obj ]] && obj=(--obj "$2" --tex-obj "$2")
  if ((reads36)); then
    "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
      "$python" "$here/qsppoly.py" "$f" "${obj[@]}" --exact-obj "$2" "${exact[@]}" --decompressed "$out" \
        --exact-decompressed "$out"
  else
    "$python" "$here/qsppoly.py" "$f" "${obj[@]}" --exact-obj "$2" "${exact[@]}"
  fi
}
whole() {  # whole FILE MESH: the text's whole decoder against MESH and what `qsp decompress` writes
  local f=$1 out exact=()
  out="$work/$(basename "$f" .qsp)_$BASHPID.obj"
  [[ $f == *_keep_order.qsp ]] && exact=(--exact)  # the original numbering kept: index for index
  "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
    "$python" "$here/qsppoly.py" "$f" --obj "$2" --tex-obj "$2" "${exact[@]}" --decompressed "$out"
}
labelled() {  # labelled FILE MESH: face labels against MESH and what `qsp decompress` writes
  local f=$1 out exact=()
  out="$work/$(basename "$f" .qsp)_$BASHPID.obj"
  [[ $(basename "$f") == *keep_order* ]] && exact=(--exact)  # the original face order kept
  "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
    "$python" "$here/qsppoly.py" "$f" --labels-obj "$2" "${exact[@]}" --labels-decompressed "$out" \
      --decompressed "$out"
}
tagged() {  # tagged FILE MESH: the whole mesh, labels and tags against MESH and what `qsp decompress` writes
  local f=$1 out exact=()
  out="$work/$(basename "$f" .qsp)_$BASHPID.obj"
  [[ -n ${tag_exact[$f]:-} ]] && exact=(--exact)
  "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
    "$python" "$here/qsppoly.py" "$f" --obj "$2" --tex-obj "$2" --labels-obj "$2" --tags-obj "$2" "${exact[@]}" \
      --decompressed "$out" --labels-decompressed "$out" --tags-decompressed "$out"
}
normalled() {  # normalled FILE MESH: the whole mesh, normals included, against MESH and what `qsp decompress` writes
  local f=$1 out exact=() against=(--normals-obj "$2")
  out="$work/$(basename "$f" .qsp)_$BASHPID.obj"
  [[ -n ${nrm_exact[$f]:-} ]] && exact=(--exact)
  # Octahedral normals (_qn) are compared with what qsp decompress writes only.
  [[ $(basename "$f") == *_qn* ]] && against=()
  "$qsp" decompress -f "$f" -o "$out" >/dev/null &&
    "$python" "$here/qsppoly.py" "$f" --obj "$2" --tex-obj "$2" --labels-obj "$2" --tags-obj "$2" "${against[@]}" \
      "${exact[@]}" --decompressed "$out" --labels-decompressed "$out" --tags-decompressed "$out" \
      --normals-decompressed "$out"
}
check() {  # check FILE: the text's decoder against the reference's dump (prints nothing on success)
  local f=$1 prefix
  if [[ -n ${val_of[$f]:-} ]]; then
    valued "$f" "${val_of[$f]}" || { echo "spec decoder's exact values disagree: $f" >&2; return 1; }
    [[ -n ${val_only[$f]:-} ]] && return 0
  fi
  if [[ -n ${exa_of[$f]:-} ]]; then
    exacted "$f" "${exa_of[$f]}" || { echo "spec decoder's exact positions disagree: $f" >&2; return 1; }
    return 0
  fi
  if [[ -n ${nrm_of[$f]:-} ]]; then
    normalled "$f" "${nrm_of[$f]}" || { echo "spec decoder's mesh with normals disagrees: $f" >&2; return 1; }
    return 0
  fi
  if [[ -n ${tag_of[$f]:-} ]]; then
    tagged "$f" "${tag_of[$f]}" || { echo "spec decoder's mesh with subdivision tags disagrees: $f" >&2; return 1; }
    return 0
  fi
  if [[ -n ${tex_of[$f]:-} ]]; then  # (the reference's dump reads no texture coordinates)
    whole "$f" "${tex_of[$f]}" || { echo "spec decoder's mesh with texture coordinates disagrees: $f" >&2; return 1; }
    return 0
  fi
  if [[ -n ${lab_of[$f]:-} ]]; then
    labelled "$f" "${lab_of[$f]}" || { echo "spec decoder's mesh with face labels disagrees: $f" >&2; return 1; }
    return 0
  fi
  if [[ -n ${interior[$f]:-} ]]; then
    whole "$f" "${obj_of[$f]}" ||
      { echo "spec decoder's polygon mesh with interior positions disagrees: $f" >&2; return 1; }
    return 0
  fi
  prefix="$work/$(basename "$f" .qsp)_$BASHPID"
  if ! "$dump" "$f" "$prefix" || ! "$python" "$here/qspgeo.py" "$f" "$prefix"; then
    echo "spec decoder disagrees: $f" >&2
    return 1
  elif [[ -n ${obj_of[$f]:-} ]] && ! "$python" "$here/qsppoly.py" "$f" --obj "${obj_of[$f]}" --reference "$prefix"; then
    echo "spec decoder's whole mesh disagrees: $f" >&2
    return 1
  elif [[ $f == *_keep_order.qsp && -n ${obj_of[$f]:-} ]] && ! whole "$f" "${obj_of[$f]}"; then
    echo "spec decoder's mesh in its original order disagrees: $f" >&2
    return 1
  elif [[ -n ${original[$f]:-} ]] && ! cmp -s "$prefix.pos" "${original[$f]}"; then
    echo "the reference decodes a recoded file to other positions than its original: $f" >&2
    return 1
  fi
}
# Files with an interior positions section (3.12): dump_stencils reads a polygon file's counts,
# topology and geometry as a file of its quad submesh, which such a file's geometry is not (it codes
# the interior positions too); they are decoded whole against their mesh and what `qsp decompress`
# writes instead.
declare -A interior=()
while read -r f; do interior[$f]=1; done < <("$python" - "$here" "${!obj_of[@]}" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import qspgeo as g
for f in sys.argv[2:]:
    if 0x0c in g.sections(open(f, 'rb').read()):
        print(f)
PY
)
# Files are independent: as many at once as there are cores (the Python decoder is the long pole of
# the release suite).
declare -A queued=()  # golden files with exact values that no check above takes: their values alone
for f in "${!nrm_of[@]}" "${!tag_of[@]}" "${!lab_of[@]}" "${!tex_of[@]}" "${files[@]}"; do queued[$f]=1; done
for f in "${!val_of[@]}"; do [[ -n ${queued[$f]:-} ]] || val_only[$f]=1; done
failed=0 running=0
for f in "${!nrm_of[@]}" "${!tag_of[@]}" "${!lab_of[@]}" "${!tex_of[@]}" "${files[@]}" "${!val_only[@]}"; do
  if ((running >= $(nproc))); then
    wait -n || failed=1
    running=$((running - 1))
  fi
  check "$f" &
  running=$((running + 1))
done
while ((running)); do
  wait -n || failed=1
  running=$((running - 1))
done
echo "spec decoder: $((${#files[@]} + ${#tex_of[@]} + ${#lab_of[@]} + ${#tag_of[@]} + ${#nrm_of[@]})) files checked, $((${#obj_of[@]} + ${#tex_of[@]} + ${#lab_of[@]} + ${#tag_of[@]} + ${#nrm_of[@]})) of them decoded whole against their mesh, ${#interior[@]} polygon files with interior positions, ${#tex_of[@]} with texture coordinates, ${#lab_of[@]} with face labels, ${#tag_of[@]} with subdivision tags, ${#nrm_of[@]} with normals; $colors_checked golden files with colours; ${#val_of[@]} with exact values (${#values_tests[@]} of them broken each way the text names); $props_checked with properties (each broken each way the text names)"
exit $failed
