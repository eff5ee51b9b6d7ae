#!/usr/bin/env bash
# Texture coordinates (issue 19): the all-quad corpus meshes with UVs, as OBJ files holding positions,
# texture coordinates and faces (v, vt, f v/vt; normals, groups and materials left out, as qsp does not
# keep them yet): `qsp compress --best --quantize 14 --quantize-uv 12` against `draco_encoder -qp 14
# -qt 12 -cl 10 -preserve_polygons` on the same file, the texture coordinates' own cost in each (qsp:
# its texture coordinates section, `qsp stats --json`; Draco: its file minus the positions-only file's),
# and the lossless default against `xz -9` of the same OBJ text. Every qsp file is decompressed and
# checked to hold the same faces and texture coordinate count.
#
#   tools/bench/bench_texcoords.sh [MESH.obj ...]
#       default: ../shared/meshes/{keenan_spot_quadrangulated, keenan_blub_quadrangulated, mh_base,
#       mh_female_generic, mh_male_casualsuit01, mh_fedora}.obj, issue 19's six
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
  for n in keenan_spot_quadrangulated keenan_blub_quadrangulated mh_base mh_female_generic \
    mh_male_casualsuit01 mh_fedora; do
    meshes+=("$shared/$n.obj")
  done
fi
for tool in python3 awk xz draco_encoder; do
  command -v "$tool" >/dev/null || { echo "bench_texcoords: $tool not found (tools/setup.sh --bench)" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_texcoords: $QSP not built" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

size() { stat -c %s "$1"; }
# Faces (v/vt pairs, in order) and the number of vt lines: what must come back with --keep-order.
shape() { awk '$1 == "f" { print } $1 == "vt" { n++ } END { print n + 0 }' "$1" | md5sum; }

printf '%-28s %7s %6s | %8s %8s %6s | %7s %7s | %8s %8s %6s\n' mesh V vt "qsp" "Draco" "ratio" \
  "qsp uv" "Dr. uv" "lossless" "xz -9" "ratio"
for mesh in "${meshes[@]}"; do
  [ -f "$mesh" ] || continue
  name=$(basename "$mesh" .obj)
  in=$work/in.obj
  awk '$1 == "v" { print "v", $2, $3, $4; next }
       $1 == "vt" { print "vt", $2, $3; next }
       $1 == "f" { printf "f"; for (i = 2; i <= NF; i++) { split($i, a, "/"); printf " %s/%s", a[1], a[2] } printf "\n" }' \
    "$mesh" > "$in"
  awk -f "$here/positions_only.awk" "$mesh" > "$work/p.obj"
  "$QSP" compress -f -q --best --quantize 14 --quantize-uv 12 "$in" "$work/q.qsp"
  "$QSP" compress -f -q "$in" "$work/l.qsp"
  "$QSP" compress -f -q --keep-order "$in" "$work/k.qsp"
  "$QSP" decompress -f -q "$work/k.qsp" "$work/k.obj"
  [ "$(shape "$in")" = "$(shape "$work/k.obj")" ] || { echo "bench_texcoords: $name: faces or UVs changed" >&2; exit 1; }
  draco_encoder -i "$in" -o "$work/d.drc" -qp 14 -qt 12 -cl 10 -preserve_polygons >/dev/null
  draco_encoder -i "$work/p.obj" -o "$work/dp.drc" -qp 14 -cl 10 -preserve_polygons >/dev/null
  xz -9 -k -c "$in" > "$work/in.xz"
  uv=$("$QSP" stats --json "$work/q.qsp" | python3 -c 'import json, sys; print(json.load(sys.stdin)[0]["bytes"]["texcoords"])')
  v=$(grep -c '^v ' "$in")
  t=$(grep -c '^vt ' "$in")
  printf '%-28s %7s %6s | %8s %8s %6.3f | %7s %7s | %8s %8s %6.3f\n' "$name" "$v" "$t" \
    "$(size "$work/q.qsp")" "$(size "$work/d.drc")" "$(echo "$(size "$work/q.qsp") / $(size "$work/d.drc")" | bc -l)" \
    "$uv" "$(($(size "$work/d.drc") - $(size "$work/dp.drc")))" \
    "$(size "$work/l.qsp")" "$(size "$work/in.xz")" "$(echo "$(size "$work/l.qsp") / $(size "$work/in.xz")" | bc -l)"
done
