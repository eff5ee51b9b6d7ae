#!/usr/bin/env bash
# qsp beside the tools users would pick instead (issue 3, "Benchmark against the tools users would
# pick instead"): Draco, meshoptimizer's codecs, zstd -19 and xz -9 of the OBJ. File sizes on every
# valid all-quad mesh of ../shared/meshes, then whole-process time and peak memory on one big mesh.
#
#   tools/bench/bench_codec.sh [MESHDIR]        default ../shared/meshes
#
# Environment: BUILD (default build; holds qsp and meshopt_codec), QSP, MESHOPT (override those),
#   RUNS (hyperfine runs, default 10), TIME_MESH (default mh_female_generic_cc2.obj; empty: no timing),
#   KEEP (a folder to keep the work files in; default a temporary folder, removed at exit).
# Needs: tools/setup.sh --bench (draco, libmeshoptimizer-dev, zstd, xz-utils, hyperfine, time),
#   python3, and a build with -DQSP_BUILD_BENCH=ON (for meshopt_codec).
#
# Input: for each MANIFEST.tsv row with all_quad=True and no non-manifold or degenerate element, a
# positions-only OBJ that every tool reads: .obj files go through an awk filter that keeps the `v`
# lines (first three coordinates, the author's text unchanged) and the `f` lines with only the
# vertex indices (v/vt/vn -> v); texture coordinates, normals, groups, materials and OpenSubdiv tags
# are dropped. .off files (Draco reads no OFF) are converted with
# `qsp compress --positions-only --float32 --keep-order` + `qsp decompress` (shortest float text, same order).
#
# Per mesh:
#   qsp       `qsp compress` (lossless, float32 bit-exact) and `--quantize 14`; byte split from
#             `qsp stats --json` (connectivity, geometry; the rest is header and checksum). The
#             lossless file is decompressed and compressed again: the bytes must be identical.
#   draco     `draco_encoder -qp 14 -cl 10 -preserve_polygons` (quads kept); connectivity estimated
#             as the size of the same command at -qp 1 (an upper bound: it still holds 1-bit
#             positions), geometry as the difference; the file is decoded with draco_decoder.
#   meshopt   tools/bench/meshopt_codec.cpp: quads as 2 triangles each, optimizeVertexCache +
#             optimizeVertexFetch, encodeIndexBuffer (quads kept: a quad's triangles side by side),
#             encodeVertexBuffer on float32 xyz (lossless) and on 14-bit positions in uint16, zstd -19
#             per stream.
#   zstd/xz   `zstd -19` and `xz -9` of the positions-only OBJ.
# Timing (TIME_MESH): hyperfine, whole processes writing their output files: qsp compress
# (--quantize 14, and lossless) vs draco_encoder -qp 14 -cl 7 -preserve_polygons; qsp decompress vs
# draco_decoder (both write OBJ). Peak RSS from /usr/bin/time -v, median of 3 runs.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
BUILD=${BUILD:-$root/build}
QSP=${QSP:-$BUILD/qsp}
MESHOPT=${MESHOPT:-$BUILD/meshopt_codec}
RUNS=${RUNS:-10}
TIME_MESH=${TIME_MESH-mh_female_generic_cc2.obj}
MESHDIR=$(cd "${1:-$root/../shared/meshes}" && pwd)
BITS=14

for tool in python3 awk draco_encoder draco_decoder zstd xz hyperfine /usr/bin/time; do
  command -v "$tool" >/dev/null || { echo "bench_codec: $tool not found (tools/setup.sh --bench)" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_codec: $QSP not built (set BUILD=... or QSP=...)" >&2; exit 2; }
[ -x "$MESHOPT" ] || { echo "bench_codec: $MESHOPT not built (cmake -DQSP_BUILD_BENCH=ON, target meshopt_codec)" >&2; exit 2; }
[ -f "$MESHDIR/MANIFEST.tsv" ] || { echo "bench_codec: no $MESHDIR/MANIFEST.tsv" >&2; exit 2; }

if [ -n "${KEEP:-}" ]; then
  work=$KEEP; mkdir -p "$work"
else
  work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fi

size() { stat -c %s "$1"; }

# Positions-only OBJ of $1 into $2.
positions_only() {
  case "$1" in
    *.obj)
      awk -f "$here/positions_only.awk" "$1" > "$2" ;;
    *)
      "$QSP" compress -f --positions-only --float32 --keep-order "$1" "$work/conv.qsp"
      "$QSP" decompress -f "$work/conv.qsp" "$2" ;;
  esac
}

# Valid all-quad meshes from the manifest (columns by name).
mapfile -t meshes < <(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["all_quad"] == "True" && $c["nonmanifold_edges"] == 0 && $c["nonmanifold_vertices"] == 0 &&
  $c["degenerate_faces"] == 0 { print $c["name"] }' "$MESHDIR/MANIFEST.tsv")
skipped=$(awk -F'\t' 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["all_quad"] == "True" && ($c["nonmanifold_edges"] != 0 || $c["nonmanifold_vertices"] != 0 ||
  $c["degenerate_faces"] != 0) { printf "%s ", $c["name"] }' "$MESHDIR/MANIFEST.tsv")

rows=$work/rows.tsv
: > "$rows"
for name in "${meshes[@]}"; do
  echo "bench_codec: $name" >&2
  d=$work/${name%.*}
  mkdir -p "$d"
  obj=$d/p.obj
  positions_only "$MESHDIR/$name" "$obj"
  "$QSP" compress -f "$obj" "$d/l.qsp"
  "$QSP" compress -f --quantize $BITS "$obj" "$d/q.qsp"
  "$QSP" decompress -f "$d/l.qsp" "$d/l.obj"
  "$QSP" compress -f "$d/l.obj" "$d/l2.qsp"
  cmp -s "$d/l.qsp" "$d/l2.qsp" || { echo "bench_codec: $name: qsp round trip changed the bytes" >&2; exit 1; }
  ql=$("$QSP" stats --json "$d/l.qsp")
  qq=$("$QSP" stats --json "$d/q.qsp")
  draco_encoder -i "$obj" -o "$d/q.drc" -qp $BITS -cl 10 -preserve_polygons >/dev/null
  draco_encoder -i "$obj" -o "$d/c.drc" -qp 1 -cl 10 -preserve_polygons >/dev/null
  draco_decoder -i "$d/q.drc" -o "$d/q_drc.obj" >/dev/null
  mo=$("$MESHOPT" --tsv --bits $BITS "$obj")
  zs=$(zstd -19 -q -c "$obj" | wc -c)
  xzs=$(xz -9 -c "$obj" | wc -c)
  python3 - "$name" "$(size "$obj")" "$ql" "$qq" "$(size "$d/q.drc")" "$(size "$d/c.drc")" "$mo" "$zs" "$xzs" \
    >> "$rows" <<'EOF'
import json, sys
name, objb, ql, qq, drc, drc1, mo, zs, xzs = sys.argv[1:]
ql, qq = json.loads(ql)[0], json.loads(qq)[0]  # stats --json is always an array
mv, mq, mi, mit, mf, mqz = map(int, mo.split())
V = ql["mesh"]["vertices"]
assert mv == V, (name, mv, V)
out = [name, V, objb, ql["bytes"]["total"], ql["bytes"]["connectivity"], ql["bytes"]["geometry"],
       qq["bytes"]["total"], qq["bytes"]["connectivity"], qq["bytes"]["geometry"], drc, drc1,
       mi, mit, mf, mqz, zs, xzs]
print("\t".join(map(str, out)))
EOF
done

python3 - "$rows" "$BITS" "$skipped" <<'EOF'
import sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
bits, skipped = sys.argv[2], sys.argv[3].split()
def bpv(b, v): return 8.0 * b / v
print(f"\n### Lossless (float32 bit-exact)\n")
print("| mesh | V | OBJ bytes | qsp bytes | qsp conn/geom bits/v | meshopt+zstd bytes | meshopt idx/geom bits/v "
      "| zstd -19 | xz -9 | xz bits/v | qsp / xz |")
print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
worst_l = 0.0
for r in rows:
    name, V, objb, lt, lc, lg, qt, qc, qg, drc, drc1, mi, mit, mf, mqz, zs, xzs = r[0], *map(int, r[1:])
    ratio = lt / xzs
    worst_l = max(worst_l, ratio)
    print(f"| {name} | {V} | {objb} | {lt} | {bpv(lc, V):.2f} / {bpv(lg, V):.1f} | {mi + mf} | "
          f"{bpv(mi, V):.1f} / {bpv(mf, V):.1f} | {zs} | {xzs} | {bpv(xzs, V):.1f} | {ratio:.3f} |")
print(f"\n### {bits}-bit positions (`qsp compress --quantize {bits}`, `draco_encoder -qp {bits} -cl 10 "
      "-preserve_polygons`)\n")
print(f"| mesh | V | qsp bytes | qsp conn/geom bits/v | qsp bits/v | Draco bytes | Draco conn (-qp 1) / geom bits/v "
      f"| Draco bits/v | meshopt+zstd bytes | meshopt idx/geom bits/v | qsp conn / Draco -qp 1 | qsp / Draco |")
print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
worst_q, cc2 = 0.0, None
for r in rows:
    name, V, objb, lt, lc, lg, qt, qc, qg, drc, drc1, mi, mit, mf, mqz, zs, xzs = r[0], *map(int, r[1:])
    ratio = qt / drc
    worst_q = max(worst_q, ratio)
    if name == "mh_female_generic_cc2.obj": cc2 = ratio
    print(f"| {name} | {V} | {qt} | {bpv(qc, V):.2f} / {bpv(qg, V):.1f} | {bpv(qt, V):.1f} | {drc} | "
          f"{bpv(drc1, V):.1f} / {bpv(drc - drc1, V):.1f} | {bpv(drc, V):.1f} | {mi + mqz} | "
          f"{bpv(mi, V):.1f} / {bpv(mqz, V):.1f} | {qc / drc1:.3f} | {ratio:.3f} |")
print("\nmeshopt index: quads kept (each quad's two triangles side by side); the plain cache-optimized "
      "triangle list, which loses the quads, costs idx bits/v: " +
      ", ".join(f"{r[0].rsplit('.', 1)[0]} {bpv(int(r[12]), int(r[1])):.1f}" for r in rows))
if skipped: print(f"skipped (not valid quad meshes): {' '.join(skipped)}")
def verdict(ok): return "met" if ok else "NOT met"
print(f"\nTargets (sizes):")
nq = sum(int(r[6]) <= 0.67 * int(r[9]) for r in rows)
nl = sum(int(r[3]) <= 0.6 * int(r[16]) for r in rows)
print(f"- --quantize {bits} <= 0.67x Draco on every all-quad mesh: worst {worst_q:.3f}, within on {nq} of "
      f"{len(rows)} -> {verdict(worst_q <= 0.67)}")
if cc2 is not None:
    print(f"- --quantize {bits} <= 0.5x Draco on mh_female_generic_cc2.obj: {cc2:.3f} -> {verdict(cc2 <= 0.5)}")
print(f"- lossless <= 0.6x xz -9 of the OBJ on every mesh: worst {worst_l:.3f}, within on {nl} of {len(rows)} "
      f"-> {verdict(worst_l <= 0.6)}")
EOF

[ -n "$TIME_MESH" ] || exit 0
name=$TIME_MESH
d=$work/${name%.*}
obj=$d/p.obj
[ -f "$obj" ] || { echo "bench_codec: $name was not among the meshes" >&2; exit 1; }
echo "bench_codec: timing on $name ($RUNS runs each)" >&2
draco_encoder -i "$obj" -o "$d/t.drc" -qp $BITS -cl 7 -preserve_polygons >/dev/null
"$QSP" compress -f --quantize $BITS "$obj" "$d/t.qsp"
enc_json=$work/enc.json
dec_json=$work/dec.json
hyperfine -N --warmup 1 --runs "$RUNS" --export-json "$enc_json" --style basic \
  -n "qsp compress --quantize $BITS" "$QSP compress -f --quantize $BITS $obj $d/t.qsp" \
  -n "qsp compress (lossless)" "$QSP compress -f $obj $d/tl.qsp" \
  -n "draco_encoder -qp $BITS -cl 7" "draco_encoder -i $obj -o $d/t.drc -qp $BITS -cl 7 -preserve_polygons" >&2
hyperfine -N --warmup 1 --runs "$RUNS" --export-json "$dec_json" --style basic \
  -n "qsp decompress ($BITS-bit)" "$QSP decompress -f $d/t.qsp $d/t_qsp.obj" \
  -n "qsp decompress (lossless)" "$QSP decompress -f $d/tl.qsp $d/tl_qsp.obj" \
  -n "draco_decoder ($BITS-bit)" "draco_decoder -i $d/t.drc -o $d/t_drc.obj" >&2

# Peak resident set size (kB), median of 3 runs.
rss() {
  local a=()
  for _ in 1 2 3; do
    /usr/bin/time -v -o "$work/time.txt" "$@" >/dev/null 2>&1
    a+=("$(awk -F': ' '/Maximum resident set size/ { print $2 }' "$work/time.txt")")
  done
  printf '%s\n' "${a[@]}" | sort -n | sed -n 2p
}
rss_file=$work/rss.tsv
{
  printf 'qsp compress --quantize %s\t%s\n' $BITS "$(rss "$QSP" compress -f --quantize $BITS "$obj" "$d/t.qsp")"
  printf 'qsp compress (lossless)\t%s\n' "$(rss "$QSP" compress -f "$obj" "$d/tl.qsp")"
  printf 'draco_encoder -qp %s -cl 7\t%s\n' $BITS "$(rss draco_encoder -i "$obj" -o "$d/t.drc" -qp $BITS -cl 7 -preserve_polygons)"
  printf 'qsp decompress (%s-bit)\t%s\n' $BITS "$(rss "$QSP" decompress -f "$d/t.qsp" "$d/t_qsp.obj")"
  printf 'qsp decompress (lossless)\t%s\n' "$(rss "$QSP" decompress -f "$d/tl.qsp" "$d/tl_qsp.obj")"
  printf 'draco_decoder (%s-bit)\t%s\n' $BITS "$(rss draco_decoder -i "$d/t.drc" -o "$d/t_drc.obj")"
} > "$rss_file"

python3 - "$enc_json" "$dec_json" "$rss_file" "$name" "$BITS" "$(nproc)" <<'EOF'
import json, sys
enc, dec = (json.load(open(p))["results"] for p in sys.argv[1:3])
rss = dict(l.rstrip("\n").split("\t") for l in open(sys.argv[3]))
name, bits, cpus = sys.argv[4], sys.argv[5], sys.argv[6]
print(f"\n### Whole-process time and peak memory on {name} ({cpus} CPUs, mean ± sd of "
      f"{len(enc[0]['times'])} runs, hyperfine -N)\n")
print("| command | wall s | user+sys s | peak RSS MB | draco time / this | draco RSS / this |")
print("|---|--:|--:|--:|--:|--:|")
verdicts = []
for res, label in ((enc, "compress"), (dec, "decompress")):
    draco = res[-1]
    dr = int(rss[draco["command"]])
    for x in res:
        r = int(rss[x["command"]])
        print(f"| {x['command']} | {x['mean']:.3f} ± {x['stddev']:.3f} | {x['user'] + x['system']:.3f} | "
              f"{r / 1024:.1f} | {draco['mean'] / x['mean']:.2f}x | {dr / r:.2f}x |")
    for q, mode in ((res[0], f"{bits}-bit, as Draco"), (res[1], "lossless, vs Draco at 14-bit")):
        speed = draco["mean"] / q["mean"]
        cpu = (draco["user"] + draco["system"]) / (q["user"] + q["system"])
        mem = dr / int(rss[q["command"]])
        verdicts.append(f"- {label} ({mode}) >= 2x faster than Draco -cl 7: wall {speed:.2f}x "
                        f"(cpu {cpu:.2f}x) -> {'met' if speed >= 2 else 'NOT met'}; lower peak memory: "
                        f"{mem:.2f}x less -> {'met' if mem > 1 else 'NOT met'}")
print("\nTargets (time, memory):")
print("\n".join(verdicts))
EOF
