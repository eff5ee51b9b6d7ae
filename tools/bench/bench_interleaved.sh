#!/usr/bin/env bash
# Whole-process wall times of qsp and Draco, the issue-18 way: per mesh, qsp compress and
# draco_encoder run in turn ROUNDS times (A B A B ..., after a warm-up of each), the ratio taken pair by
# pair and its median printed; the same for qsp decompress and draco_decoder. A slow minute on a shared
# machine then hits both commands of a pair alike. Times come from bash's EPOCHREALTIME (microseconds:
# GNU time's 10 ms steps are a quarter of a small mesh's run).
#
#   tools/bench/bench_interleaved.sh [MESH.obj ...]
#       default: ../shared/meshes/{keenan_spot_quadrangulated, quadriflow_gargoyle, mh_female_generic,
#       mh_base, mh_female_generic_cc2}.obj, issue 18's five
#
# Input: a positions-only OBJ both tools read the same way (v and f lines, vertex indices only).
# Commands: `qsp compress -f [LEVEL] --quantize BITS` against `draco_encoder -qp BITS -cl 7
# -preserve_polygons`; `qsp decompress -f` against `draco_decoder`, both writing OBJ.
# Environment: QSP (default build/qsp), ROUNDS (default 15), BITS (default 14), LEVEL (default: none,
# the default level; e.g. -9), QSP_OTHER (optional: a second qsp binary, paired against QSP instead of
# Draco, e.g. the previous commit's build), ATTRIBUTES=1 (issue 19's speed: the whole OBJ, UVs, normals and
# labels included, with `--quantize-uv 12 --quantize-normal 10` against Draco's `-qt 12 -qn 10`).
# Needs: draco (draco_encoder, draco_decoder), bash 5, python3.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shared=$root/../shared/meshes
QSP=${QSP:-$root/build/qsp}
QSP_OTHER=${QSP_OTHER:-}
ROUNDS=${ROUNDS:-15}
BITS=${BITS:-14}
LEVEL=${LEVEL:-}
meshes=("$@")
if ((${#meshes[@]} == 0)); then
  for n in keenan_spot_quadrangulated quadriflow_gargoyle mh_female_generic mh_base mh_female_generic_cc2; do
    meshes+=("$shared/$n.obj")
  done
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

elapsed() {  # command... ; prints its wall time in seconds
  local t0=$EPOCHREALTIME
  "$@" > /dev/null 2>&1 || { echo "failed: $*" >&2; exit 1; }
  local t1=$EPOCHREALTIME
  echo "${t0/[.,]/} ${t1/[.,]/}" | awk '{printf "%.6f\n", ($2 - $1) / 1e6}'
}

printf '%-28s %7s | %9s %9s %7s | %9s %9s %7s\n' mesh V "compress" "vs" "ratio" "decomp." "vs" "ratio"
for mesh in "${meshes[@]}"; do
  name=$(basename "$mesh" .obj)
  attr_q=() attr_d=()
  if [ "${ATTRIBUTES:-0}" = 1 ]; then
    cp "$mesh" "$work/in.obj"
    attr_q=(-q --quantize-uv 12 --quantize-normal 10) attr_d=(-qt 12 -qn 10)
  else
    awk -f "$here/positions_only.awk" "$mesh" > "$work/in.obj"
  fi
  qc=("$QSP" compress -f $LEVEL --quantize "$BITS" "${attr_q[@]}" "$work/in.obj" "$work/q.qsp")
  qd=("$QSP" decompress -f "$work/q.qsp" "$work/q.obj")
  if [ -n "$QSP_OTHER" ]; then
    bc=("$QSP_OTHER" compress -f $LEVEL --quantize "$BITS" "${attr_q[@]}" "$work/in.obj" "$work/o.qsp")
    bd=("$QSP_OTHER" decompress -f "$work/o.qsp" "$work/o.obj")
  else
    bc=(draco_encoder -i "$work/in.obj" -o "$work/d.drc" -qp "$BITS" "${attr_d[@]}" -cl 7 -preserve_polygons)
    bd=(draco_decoder -i "$work/d.drc" -o "$work/d.obj")
  fi
  : > "$work/t"
  for ((r = -1; r < ROUNDS; ++r)); do  # round -1: the warm-up, not counted
    a=$(elapsed "${qc[@]}"); b=$(elapsed "${bc[@]}"); c=$(elapsed "${qd[@]}"); d=$(elapsed "${bd[@]}")
    ((r >= 0)) && echo "$a $b $c $d" >> "$work/t"
  done
  v=$(grep -c '^v ' "$work/in.obj")
  python3 - "$work/t" "$name" "$v" <<'PY'
import sys, statistics as st
rows = [list(map(float, l.split())) for l in open(sys.argv[1])]
med = lambda k: st.median(r[k] for r in rows) * 1000
ratio = lambda a, b: st.median(r[a] / r[b] for r in rows)
print(f"{sys.argv[2]:28s} {int(sys.argv[3]):7d} | {med(0):7.1f}ms {med(1):7.1f}ms {ratio(0, 1):6.2f}x"
      f" | {med(2):7.1f}ms {med(3):7.1f}ms {ratio(2, 3):6.2f}x")
PY
done
echo "(median wall of $ROUNDS rounds each; ratio = qsp / $([ -n "$QSP_OTHER" ] && echo "$QSP_OTHER" || echo Draco), median of the per-round ratios)"
