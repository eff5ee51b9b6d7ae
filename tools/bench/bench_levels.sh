#!/usr/bin/env bash
# File sizes of every compression level beside Draco's -cl 7 and -cl 10, on every all-quad mesh of
# ../shared/meshes (MANIFEST.tsv's all_quad column), positions only, quantized to BITS bits (default
# 14; BITS=0: lossless, beside xz -9 of the OBJ text). Prints one row per mesh: bytes per level and
# each level's ratio to Draco -cl 7 (lossless: to xz -9), then the worst ratio of each level.
#
#   tools/bench/bench_levels.sh [LEVEL ...]      default: 1 3 5 9
#
# Environment: QSP (default build/qsp), BITS (default 14). Needs: draco, xz (tools/setup.sh --bench).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
shared=$root/../shared/meshes
QSP=${QSP:-$root/build/qsp}
BITS=${BITS:-14}
levels=("$@")
((${#levels[@]})) || levels=(1 3 5 9)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
header="mesh"
for l in "${levels[@]}"; do header+="\t-$l"; done
if ((BITS)); then header+="\tdraco7\tdraco10"; else header+="\txz-9"; fi
for l in "${levels[@]}"; do header+="\t-$l/ref"; done
((BITS)) && header+="\t-9/draco10"
printf '%b\n' "$header"
awk -F'\t' 'NR > 1 && $11 == "True" {print $1}' "$shared/MANIFEST.tsv" | while read -r name; do
  src=$shared/$name
  [[ -f $src ]] || continue
  ext=${name##*.}
  if [[ $ext == obj ]]; then  # positions only: v and f lines, vertex indices only
    awk -f "$here/positions_only.awk" \
      "$src" > "$work/in.obj"
  else  # OFF: Draco reads OBJ; qsp's --keep-order round trip writes the same mesh as OBJ (float32)
    rm -f "$work/in.obj"  # a refused conversion must not leave the previous mesh to be measured
    "$QSP" compress -f --keep-order --float32 "$src" "$work/t.qsp" && "$QSP" decompress -f "$work/t.qsp" "$work/in.obj"
  fi
  in=$work/in.obj
  if ! "$QSP" compress -f -1 "$in" "$work/q.qsp" 2> "$work/err"; then
    echo "$name: refused by qsp ($(head -c 80 "$work/err")), skipped" >&2
    continue
  fi
  row="$name"
  sizes=()
  for l in "${levels[@]}"; do
    if ((BITS)); then
      "$QSP" compress -f "-$l" --quantize "$BITS" "$in" "$work/q.qsp"
    else
      "$QSP" compress -f "-$l" "$in" "$work/q.qsp"
    fi
    sizes+=("$(stat -c %s "$work/q.qsp")")
    row+="\t${sizes[-1]}"
  done
  if ((BITS)); then
    draco_encoder -i "$in" -o "$work/d7.drc" -qp "$BITS" -cl 7 -preserve_polygons > /dev/null
    draco_encoder -i "$in" -o "$work/d10.drc" -qp "$BITS" -cl 10 -preserve_polygons > /dev/null
    ref=$(stat -c %s "$work/d7.drc")
    d10=$(stat -c %s "$work/d10.drc")
    row+="\t$ref\t$d10"
  else
    ref=$(xz -9 -c "$in" | wc -c)
    row+="\t$ref"
  fi
  for s in "${sizes[@]}"; do row+="\t$(python3 -c "print(f'{$s / $ref:.3f}')")"; done
  ((BITS)) && row+="\t$(python3 -c "print(f'{${sizes[-1]} / $d10:.3f}')")"
  printf '%b\n' "$row"
done | tee "$work/rows"
python3 - "$work/rows" "${#levels[@]}" "$BITS" <<'PY'
import sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])]
n, bits = int(sys.argv[2]), int(sys.argv[3])
if rows:
    first = 1 + n + (2 if bits else 1)  # the per-level ratio columns
    worst = [max(float(r[c]) for r in rows) for c in range(first, first + n + (1 if bits else 0))]
    print("worst\t" + "\t" * (n + (2 if bits else 1)) + "\t".join(f"{w:.3f}" for w in worst))
PY
