#!/usr/bin/env bash
# Vertex colours (issue 19, format 3.8's colours section): the corpus has no coloured mesh, so each mesh
# gets per-vertex uchar colours as a scan's baked albedo would be, a smooth function of the position
# ("smooth"), and the same with +-4 of noise per channel ("noisy", as camera colours are). Written as
# binary PLY (float x y z, uchar red green blue), both tools read the same file:
# `qsp compress --best --quantize 14` (colours lossless) against `draco_encoder -qp 14 -cl 10` (its
# colours are 8-bit too, so lossless as well); each tool's colour cost is its file minus its file of the
# same PLY without colours. Lossless: the default level against `xz -9` of the PLY. Every qsp file is
# decompressed to PLY and its colours compared by position with the input's.
#
#   tools/bench/bench_colors.sh [MESH.obj ...]
#       default: ../shared/meshes/{keenan_spot_quadrangulated, quadriflow_gargoyle, mh_female_generic,
#       mh_base}.obj
#
# Environment: BUILD (default build), QSP (default $BUILD/qsp).
# Needs: tools/setup.sh --bench (draco, xz-utils), python3.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
BUILD=${BUILD:-$root/build}
QSP=${QSP:-$BUILD/qsp}
shared=$root/../shared/meshes
meshes=("$@")
if ((${#meshes[@]} == 0)); then
  for n in keenan_spot_quadrangulated quadriflow_gargoyle mh_female_generic mh_base; do
    meshes+=("$shared/$n.obj")
  done
fi
for tool in python3 xz draco_encoder; do
  command -v "$tool" >/dev/null || { echo "bench_colors: $tool not found (tools/setup.sh --bench)" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_colors: $QSP not built" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
size() { stat -c %s "$1"; }

# coloured OBJ OUT.ply MODE: the OBJ's positions and faces as binary PLY; MODE none, smooth or noisy.
coloured() {
  python3 - "$1" "$2" "$3" <<'EOF'
import math, random, struct, sys
src, out, mode = sys.argv[1:]
pos, faces = [], []
for line in open(src):
    w = line.split()
    if not w: continue
    if w[0] == 'v': pos.append(tuple(float(x) for x in w[1:4]))
    elif w[0] == 'f': faces.append([int(t.split('/')[0]) - 1 for t in w[1:]])
lo = [min(p[k] for p in pos) for k in range(3)]
hi = [max(p[k] for p in pos) for k in range(3)]
random.seed(1)
def colour(p):
    u = [(p[k] - lo[k]) / ((hi[k] - lo[k]) or 1) for k in range(3)]
    c = [128 + 100 * math.sin(5 * u[0] + 2 * u[1]), 128 + 100 * math.sin(4 * u[1] + 3 * u[2]),
         128 + 100 * math.cos(6 * u[2] + u[0])]
    if mode == 'noisy': c = [x + random.randint(-4, 4) for x in c]
    return [max(0, min(255, int(round(x)))) for x in c]
head = 'ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n' % len(pos)
if mode != 'none': head += 'property uchar red\nproperty uchar green\nproperty uchar blue\n'
head += 'element face %d\nproperty list uchar int vertex_indices\nend_header\n' % len(faces)
with open(out, 'wb') as f:
    f.write(head.encode())
    for p in pos:
        f.write(struct.pack('<3f', *p))
        if mode != 'none': f.write(bytes(colour(p)))
    for face in faces: f.write(struct.pack('<B%di' % len(face), len(face), *face))
EOF
}

# colours OUT.ply: per position, the colour (binary little-endian float x y z, uchar r g b, as both
# this script and qsp decompress write them), sorted, to compare.
colours() {
  python3 - "$1" <<'EOF'
import struct, sys
data = open(sys.argv[1], 'rb').read()
end = data.index(b'end_header\n') + len(b'end_header\n')
head = data[:end].decode().split('\n')
n = int([l for l in head if l.startswith('element vertex')][0].split()[2])
props = [l.split()[1:] for l in head if l.startswith('property') and 'list' not in l]
vprops = props[:len(props)]  # the face element here has only its list
fmt = '<' + ''.join({'float': 'f', 'double': 'd', 'uchar': 'B'}[t] for t, _ in vprops)
size = struct.calcsize(fmt)
rows = sorted(struct.unpack_from(fmt, data, end + i * size) for i in range(n))
print(hash(tuple(rows)))
EOF
}

printf '| mesh | V | colours | qsp bytes | Draco bytes | qsp / Draco | qsp colours | Draco colours | qsp lossless | xz -9 | lossless / xz |\n'
printf '|---|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|\n'
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .obj)
  coloured "$mesh" "$work/none.ply" none
  "$QSP" compress -q -f --best --quantize 14 "$work/none.ply" -o "$work/none.qsp"
  draco_encoder -i "$work/none.ply" -o "$work/none.drc" -qp 14 -cl 10 >/dev/null
  for mode in smooth noisy; do
    coloured "$mesh" "$work/$mode.ply" "$mode"
    "$QSP" compress -q -f --best --quantize 14 "$work/$mode.ply" -o "$work/$mode.qsp"
    "$QSP" compress -q -f "$work/$mode.ply" -o "$work/$mode.lossless.qsp"
    draco_encoder -i "$work/$mode.ply" -o "$work/$mode.drc" -qp 14 -cl 10 >/dev/null
    xz -9 -k -c "$work/$mode.ply" >"$work/$mode.ply.xz"
    "$QSP" decompress -q -f "$work/$mode.lossless.qsp" -o "$work/$mode.back.ply"
    [[ $(colours "$work/$mode.ply") == $(colours "$work/$mode.back.ply") ]] ||
      { echo "bench_colors: $name ($mode): colours or positions differ after the round trip" >&2; exit 1; }
    q=$(size "$work/$mode.qsp") d=$(size "$work/$mode.drc")
    ql=$(size "$work/$mode.lossless.qsp") x=$(size "$work/$mode.ply.xz")
    V=$(grep -a -m1 '^element vertex' "$work/$mode.ply" | awk '{ print $3 }')
    printf '| %s | %s | %s | %s | %s | %.3f | %s | %s | %s | %s | %.3f |\n' "$name" "$V" "$mode" "$q" "$d" \
      "$(echo "$q / $d" | bc -l)" $((q - $(size "$work/none.qsp"))) $((d - $(size "$work/none.drc"))) \
      "$ql" "$x" "$(echo "$ql / $x" | bc -l)"
  done
done
