#!/usr/bin/env bash
# Regenerates the README's pictures (docs/pictures/*.png) with `qsp show` from the shared meshes.
# Usage: tools/pictures.sh [QSP_BINARY] [MESH_DIR]   (defaults: build/qsp, ../shared/meshes)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
qsp=${1:-$root/build/qsp}
meshes=${2:-$root/../shared/meshes}
out=$root/docs/pictures
mkdir -p "$out"
size=768x768  # large enough to read the patches, small enough to keep the repository light
# name, view (azimuth,elevation: each mesh's own front), partition
while read -r name view partition; do
  "$qsp" show -f "$meshes/$name.obj" -o "$out/${name}_$partition.png" --size "$size" --view "$view" \
    --partition "$partition"
  echo "pictures: $out/${name}_$partition.png"
done <<'LIST'
keenan_spot_quadrangulated 140,15 motorcycle
keenan_spot_quadrangulated 140,15 greedy
mh_base 0,0 motorcycle
quadriflow_gargoyle 180,10 motorcycle
mh_female_generic_cc2 0,0 motorcycle
LIST
