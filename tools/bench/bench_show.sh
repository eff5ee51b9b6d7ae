#!/usr/bin/env bash
# `qsp show` whole process (issue 21): MESH drawn to a PNG at SIZE, beside `qsp stats` on the same
# mesh (reading it and tracing its motorcycle graph, what show does before it draws), so the
# difference is the picture's cost: canonical patch numbering, raster, PNG.
#
#   tools/bench/bench_show.sh [MESH]     default ../shared/meshes/mh_female_generic_cc2.obj
#
# Environment: QSP (default build/qsp), RUNS (default 15), SIZE (default 1024x1024).
# Needs hyperfine and python3 (tools/setup.sh --bench). Prints hyperfine's median wall time and its
# mean user and system CPU time per command: the machine is shared, so compare figures of one run.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
QSP=${QSP:-$root/build/qsp}
RUNS=${RUNS:-15}
SIZE=${SIZE:-1024x1024}
MESH=${1:-$root/../shared/meshes/mh_female_generic_cc2.obj}
for tool in hyperfine python3; do
  command -v "$tool" >/dev/null || { echo "bench_show: $tool not found" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_show: $QSP not built (set QSP=...)" >&2; exit 2; }
[ -f "$MESH" ] || { echo "bench_show: $MESH not found" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

echo "bench_show: $(basename "$MESH"), $SIZE, $RUNS runs each; load average $(cut -d' ' -f1-3 /proc/loadavg)"
hyperfine -N --style none --warmup 2 --runs "$RUNS" --export-json "$tmp/h.json" \
  -n "qsp stats (read + partition)" "$QSP stats $MESH" \
  -n "qsp show --size $SIZE -o out.png" "$QSP show -f $MESH -o $tmp/out.png --size $SIZE" >/dev/null
python3 - "$tmp/h.json" <<'PY'
import json, sys
print(f"{'command':36} {'median':>8} {'min':>8} {'user':>8} {'system':>8}")
for r in json.load(open(sys.argv[1]))["results"]:
    print(f"{r['command']:36} {r['median']:7.3f}s {r['min']:7.3f}s {r['user']:7.3f}s {r['system']:7.3f}s")
PY
echo "bench_show: picture $(stat -c %s "$tmp/out.png") bytes"
