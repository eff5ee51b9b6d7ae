#!/usr/bin/env bash
# Quad-dominant meshes (issue 20): every OBJ of ../shared/meshes and its osd_shapes/ with at least 90%
# quads and at least one other face, positions only, 14 bits: `qsp compress --best --quantize 14`
# against `draco_encoder -qp 14 -cl 10 -preserve_polygons`, with the cost of the faces that are not
# quads: the polygons section's counts and region codes (`qsp stats --json`, polygons_section.connectivity)
# in bits per non-quad face, beside Draco's whole connectivity in bits per face (the size at -qp 1, an
# upper bound: it still holds 1-bit positions). Each qsp file is decompressed and checked to hold the
# same number of faces of each degree.
#
#   tools/bench/bench_polygons.sh [MESHDIR]      default ../shared/meshes
#
# Environment: BUILD (default build), QSP (default $BUILD/qsp), MIN_QUADS (default 0.9).
# Needs: tools/setup.sh --bench (draco), python3.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
BUILD=${BUILD:-$root/build}
QSP=${QSP:-$BUILD/qsp}
MIN_QUADS=${MIN_QUADS:-0.9}
MESHDIR=$(cd "${1:-$root/../shared/meshes}" && pwd)
for tool in python3 awk draco_encoder; do
  command -v "$tool" >/dev/null || { echo "bench_polygons: $tool not found (tools/setup.sh --bench)" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_polygons: $QSP not built" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Faces by degree: "quads triangles ngons".
degrees() { awk '$1 == "f" { n = NF - 1; if (n == 4) q++; else if (n == 3) t++; else g++ }
                 END { print q + 0, t + 0, g + 0 }' "$1"; }

rows=$work/rows.tsv
: > "$rows"
shopt -s nullglob
for mesh in "$MESHDIR"/*.obj "$MESHDIR"/osd_shapes/*.obj; do
  name=${mesh#"$MESHDIR"/}
  obj=$work/p.obj
  awk -f "$here/positions_only.awk" "$mesh" > "$obj"
  read -r q t g < <(degrees "$obj")
  python3 -c "import sys; q, o = int(sys.argv[1]), int(sys.argv[2]); sys.exit(0 if o > 0 and q / (q + o) >= float(sys.argv[3]) else 1)" \
    "$q" $((t + g)) "$MIN_QUADS" || continue
  if ! err=$("$QSP" compress -f --best --quantize 14 "$obj" "$work/q.qsp" 2>&1); then
    printf '%s\t%s\t%s\t%s\trefused: %s\n' "$name" "$q" "$t" "$g" "$(echo "$err" | head -1)" >> "$rows"
    continue
  fi
  "$QSP" decompress -f "$work/q.qsp" "$work/back.obj"
  [ "$(degrees "$work/back.obj")" = "$q $t $g" ] || { echo "bench_polygons: $name: faces changed" >&2; exit 1; }
  draco_encoder -i "$obj" -o "$work/d.drc" -qp 14 -cl 10 -preserve_polygons >/dev/null
  draco_encoder -i "$obj" -o "$work/d1.drc" -qp 1 -cl 10 -preserve_polygons >/dev/null
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$q" "$t" "$g" "$("$QSP" stats --json "$work/q.qsp" | tr -d '\n')" \
    "$(stat -c %s "$work/d.drc")" "$(stat -c %s "$work/d1.drc")" >> "$rows"
done

python3 - "$rows" "$MIN_QUADS" <<'PY'
import json, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
print(f"Meshes with at least {float(sys.argv[2]):.0%} quads and some other face; positions only, 14 bits.\n")
print("| mesh | quads | triangles | n-gons | qsp --best bytes | Draco -cl 10 bytes | qsp / Draco "
      "| non-quad connectivity bits / non-quad face | Draco connectivity bits / face |")
print("|---|--:|--:|--:|--:|--:|--:|--:|--:|")
worst, over = 0.0, []
for r in rows:
    name, q, t, g = r[0], int(r[1]), int(r[2]), int(r[3])
    if r[4].startswith("refused"):
        print(f"| {name} | {q} | {t} | {g} | {r[4]} | | | | |")
        continue
    s = json.loads(r[4])[0]
    qsp, drc, drc1 = s["bytes"]["total"], int(r[5]), int(r[6])
    ratio = qsp / drc
    worst = max(worst, ratio)
    if ratio > 0.67: over.append(name)
    nq = t + g
    print(f"| {name} | {q} | {t} | {g} | {qsp} | {drc} | {ratio:.3f} | "
          f"{8.0 * s['polygons_section']['connectivity'] / nq:.2f} | {8.0 * drc1 / (q + nq):.2f} |")
print(f"\nworst qsp / Draco: {worst:.3f}; above 0.67: {', '.join(over) if over else 'none'}")
PY
