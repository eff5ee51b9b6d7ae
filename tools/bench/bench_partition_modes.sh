#!/usr/bin/env bash
# Schematic size per partition mode (§7) on ../shared/meshes and the bundled test meshes, and every
# mode against the known optimum on generated highway meshes (§8).
# Usage: tools/bench/bench_partition_modes.sh [BUILD_DIR]   (default build-small; built if missing)
# Extra meshes: MESHES="a.obj b.off" tools/bench/bench_partition_modes.sh
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$root/build-small}
if [[ ! -f $build/libqsp.a ]]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" --target qsp_core >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
flags=(-std=c++20 -O2 -Wall -Wextra -Wshadow -I"$root/include")
libs=("$build/libqsp.a" -lpthread -lz)
g++ "${flags[@]}" "$root/tools/bench/bench_partition_modes.cpp" "${libs[@]}" -o "$out/modes"
g++ "${flags[@]}" "$root/tools/highway/highway.cpp" "${libs[@]}" -o "$out/highway"

shopt -s nullglob
shared=("$root"/../shared/meshes/*.{obj,off,ply} ${MESHES:-})
echo "== ../shared/meshes: schematic vertices (V), edges (E), patches (P) per mode =="
"$out/modes" "${shared[@]}"
echo
echo "== ../shared/meshes/osd_shapes (medians only) =="
"$out/modes" "$root"/../shared/meshes/osd_shapes/*.obj | tail -2
echo
echo "== testdata and known answers =="
"$out/modes" "$root"/testdata/*.obj "$root"/../shared/known-answers/*.obj
echo
echo "== highway meshes: 40 seeds x 10 segments, then 20 seeds x 16 segments =="
"$out/highway" --seeds 40 --segments 10 --first 1
"$out/highway" --seeds 20 --segments 16 --size 32 --first 1000 | tail -3
