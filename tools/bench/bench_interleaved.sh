#!/usr/bin/env bash
# Whole-process times of qsp and Draco on one mesh, the four commands run in turn ROUNDS times, so a
# slow minute on a shared machine hits every command alike; prints min and median wall and user time
# and the Draco/qsp ratios of both. (bench_codec.sh runs each command's hyperfine series back to back,
# and on a noisy 2-core machine its ratios moved from 1.2x to 2.2x between runs.)
#
#   tools/bench/bench_interleaved.sh [MESH.obj]     default ../shared/meshes/mh_female_generic_cc2.obj
#
# Environment: QSP (default build/qsp), ROUNDS (default 10), BITS (default 14), QSP_OTHER (optional: a
# second qsp binary, e.g. a build of the previous format version, run in the same rounds; each
# binary decompresses its own file).
# Needs: draco (draco_encoder, draco_decoder), GNU time (/usr/bin/time).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
mesh=${1:-$root/../shared/meshes/mh_female_generic_cc2.obj}
QSP=${QSP:-$root/build/qsp}
QSP_OTHER=${QSP_OTHER:-}
ROUNDS=${ROUNDS:-10}
BITS=${BITS:-14}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Positions-only input both tools read the same way (v and f lines, vertex indices only).
awk '/^v /{print $1, $2, $3, $4} /^f /{printf "f"; for (i = 2; i <= NF; ++i) {split($i, a, "/"); printf " %s", a[1]} print ""}' \
  "$mesh" > "$work/in.obj"
run() {  # label, command...
  local label=$1
  shift
  /usr/bin/time -f "$label %e %U" "$@" > /dev/null 2>> "$work/times" || { echo "failed: $*" >&2; exit 1; }
}
for ((r = 0; r < ROUNDS; ++r)); do
  run draco_encoder draco_encoder -i "$work/in.obj" -o "$work/d.drc" -qp "$BITS" -cl 7 -preserve_polygons
  run qsp_compress "$QSP" compress -f --quantize "$BITS" "$work/in.obj" "$work/q.qsp"
  run draco_decoder draco_decoder -i "$work/d.drc" -o "$work/d.obj"
  run qsp_decompress "$QSP" decompress -f "$work/q.qsp" "$work/q.obj"
  if [ -n "$QSP_OTHER" ]; then
    run other_compress "$QSP_OTHER" compress -f --quantize "$BITS" "$work/in.obj" "$work/o.qsp"
    run other_decompress "$QSP_OTHER" decompress -f "$work/o.qsp" "$work/o.obj"
  fi
done
grep -E '^(draco_|qsp_|other_)' "$work/times" | python3 -c '
import sys, statistics as st
t = {}
for line in sys.stdin:
    k, wall, user = line.split()
    t.setdefault(k, []).append((float(wall), float(user)))
print("%-16s %9s %12s %9s %12s  (runs: %d)" % ("command", "min wall", "median wall", "min user", "median user", len(t["qsp_compress"])))
for k in ("draco_encoder", "qsp_compress", "other_compress", "draco_decoder", "qsp_decompress", "other_decompress"):
    if k not in t:
        continue
    w = [x[0] for x in t[k]]; u = [x[1] for x in t[k]]
    print(f"{k:16s} {min(w):9.2f} {st.median(w):12.2f} {min(u):9.2f} {st.median(u):12.2f}")
for a, b in (("draco_encoder", "qsp_compress"), ("draco_decoder", "qsp_decompress"),
             ("draco_encoder", "other_compress"), ("draco_decoder", "other_decompress")):
    if b not in t:
        continue
    wa = [x[0] for x in t[a]]; wb = [x[0] for x in t[b]]
    print(f"{a} / {b}: {min(wa) / min(wb):.2f}x by min wall, {st.median(wa) / st.median(wb):.2f}x by median wall")
'
