#!/usr/bin/env bash
# `qsp match` against `bliss -can` on the vertex-edge graphs of both meshes, whole process against
# whole process (issue 4, paper §6): MESH and a shuffled copy of it (random vertex numbering, face
# order and first corners).
#
#   tools/bench/bench_match.sh [MESH]        default ../shared/meshes/mh_female_generic_cc2.obj
#
# Environment: QSP (default build/qsp), RUNS (default 10), OUT (hyperfine JSON, default none).
# Needs python3, bliss and hyperfine (Debian: apt-get install -y bliss hyperfine).
#
# What each side does, per run:
#   qsp    reads both OBJ files, partitions and canonicalizes both, picks the nearest isomorphism and
#          writes the vertex map (one line per vertex).
#   bliss  reads both DIMACS graphs (prepared beforehand, not timed: bliss gets the cheaper input) and
#          computes a canonical labelling of each; the two canonical forms are then compared with cmp.
#          Run one after the other (as a script would) and, for reference, both at once.
# bliss ignores orientation (it sees only the vertex-edge graph) and returns labellings, not a map;
# turning them into a vertex map is not timed either.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
QSP=${QSP:-$root/build/qsp}
RUNS=${RUNS:-10}
MESH=${1:-$root/../shared/meshes/mh_female_generic_cc2.obj}

for tool in python3 bliss hyperfine; do
  command -v "$tool" >/dev/null || { echo "bench_match: $tool not found" >&2; exit 2; }
done
[ -x "$QSP" ] || { echo "bench_match: $QSP not built (set QSP=...)" >&2; exit 2; }
[ -f "$MESH" ] || { echo "bench_match: no $MESH" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "preparing: shuffled copy and DIMACS graphs of $(basename "$MESH")" >&2
python3 "$here/match_graphs.py" shuffle "$MESH" "$work/b.obj" 1
python3 "$here/match_graphs.py" dimacs "$MESH" "$work/a.dimacs"
python3 "$here/match_graphs.py" dimacs "$work/b.obj" "$work/b.dimacs"

# Both sides must find the meshes isomorphic (a failing command fails the benchmark).
"$QSP" match "$MESH" "$work/b.obj" -o "$work/map.txt"
qsp_cmd="'$QSP' match '$MESH' '$work/b.obj' -q -f -o '$work/map.txt'"
bliss_seq="bliss -can -ocan='$work/a.can' '$work/a.dimacs' >/dev/null && \
bliss -can -ocan='$work/b.can' '$work/b.dimacs' >/dev/null && cmp -s '$work/a.can' '$work/b.can'"
bliss_par="bliss -can -ocan='$work/a.can' '$work/a.dimacs' >/dev/null & p=\$!; \
bliss -can -ocan='$work/b.can' '$work/b.dimacs' >/dev/null && wait \$p && cmp -s '$work/a.can' '$work/b.can'"

json="${OUT:-$work/bench.json}"
hyperfine --warmup 1 --runs "$RUNS" --export-json "$json" \
  -n "qsp match" "$qsp_cmd" \
  -n "bliss -can, A then B" "$bliss_seq" \
  -n "bliss -can, A and B at once" "$bliss_par"

python3 - "$json" <<'EOF'
import json, sys
r = {x["command"]: x for x in json.load(open(sys.argv[1]))["results"]}
q = r["qsp match"]
print("\n%-30s %10s %10s %12s" % ("", "wall s", "cpu s", "vs qsp wall/cpu"))
for name, x in r.items():
    cpu = x["user"] + x["system"]
    qcpu = q["user"] + q["system"]
    print("%-30s %10.3f %10.3f %7.1fx /%5.1fx" % (name, x["mean"], cpu, x["mean"] / q["mean"], cpu / qcpu))
EOF
