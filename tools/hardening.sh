#!/usr/bin/env bash
# Hostile input (docs/hardening.md): the test suite under AddressSanitizer + UBSan (build-asan),
# the tests of the threaded seams under ThreadSanitizer (build-tsan), then every libFuzzer target
# (build-fuzz, clang) for a bounded time on seeds made from testdata/.
# Fails on any test failure, sanitizer report or fuzzer finding (crash, leak, timeout, out of memory).
#
# Usage: tools/hardening.sh [--no-asan] [--no-tsan] [--no-fuzz] [--fuzz-time SECONDS]
#   QSP_FUZZ_TIME (default 30) is the time per target; QSP_FUZZ_JOBS (default: nproc) how many run
#   at once. Findings are saved as build-fuzz/run/artifacts/TARGET-crash-*; reproduce one with
#   build-fuzz/fuzz/fuzz_TARGET FILE, then add it to testdata/invalid/fuzz/ (see testdata/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."

run_asan=1 run_tsan=1 run_fuzz=1
fuzz_time=${QSP_FUZZ_TIME:-30}
while (($#)); do
  case "$1" in
    --no-asan) run_asan=0 ;;
    --no-tsan) run_tsan=0 ;;
    --no-fuzz) run_fuzz=0 ;;
    --fuzz-time) fuzz_time=$2; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) echo "hardening.sh: unknown argument $1" >&2; exit 2 ;;
  esac
  shift
done
jobs=$(nproc)
shared=../shared
log() { printf '\n== hardening: %s\n' "$*"; }

QSP_WITH_CLANG=1 tools/setup.sh

# Warnings are enforced (-Werror) by the release build in tools/test.sh (GCC); the sanitized builds here
# use clang, which compiles them in half GCC's time, and do not use -Werror. -O1 with line tables only:
# sanitizer reports still name file:line, and the build is the longest step CI takes.
sanitized=(-G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DQSP_WERROR=OFF
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG")
# Left out under ASan: sweeps that encode and decode every corpus mesh many times over (each level and
# partition mode, every thread split) and the Python spec decoder. They take two thirds of the
# sanitized run's time, ran in the release build just before, and feed only trusted meshes; under ASan
# the same code runs on hostile input here (every bit flip and cut of every golden and small file, the
# must-fail files, the fuzz regressions) and in the fuzzers below.
asan_skip='^(spec_decoder|Levels\.EveryLevelRoundTripsAndIsCanonical|Codec\.RoundTripSharedMeshes'
asan_skip+='|Codec\.CostlyToolsRoundTripAndNeverGrowAFile|Codec\.QuantizedStaysWithinTheGrid'
asan_skip+='|PartitionModes\.EveryCorpusMeshGivesValidCanonicalPartitions'
asan_skip+='|SharedMeshesCli\.EachRoundTripsExactlyOrIsRefusedClearly|Geometry\.CoderThreadGivesTheSameBytes'
asan_skip+='|Submesh\.EverySharedMeshGivesAValidQuadSubmesh|Submesh\.SharedMeshesRenumberedGiveAnIsomorphicResult'
asan_skip+='|ReadObjParallel\.EveryCorpusObjReadsTheSameAtManySplits|Render\.ViewAndPngOnEveryCorpusMesh'
asan_skip+='|ReadObjMeshParallel\.EveryCorpusObjReadsTheSameAtManySplits'
asan_skip+='|MeshCorpus\.EveryFileRoundTripsToTheSameModelAndContent)$'
if ((run_asan)); then
  log "test suite under ASan + UBSan (build-asan), without the corpus sweeps (asan_skip)"
  start=$SECONDS
  cmake -S . -B build-asan "${sanitized[@]}" -DQSP_SANITIZE=ON >/dev/null
  cmake --build build-asan --target qsp_tests -j"$jobs"  # and the CLI it runs; not dump_stencils (skipped)
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    ctest --test-dir build-asan --output-on-failure --no-tests=error -j"$jobs" -E "$asan_skip"
  echo "hardening: sanitized suite passed in $((SECONDS - start)) s"
fi

# Each threaded path's seam test (CONTRIBUTING.md, "Threads"): the OBJ read (into a QuadMesh and into a
# Mesh) and text write split over two threads, the geometry coder's thread, the partitions tried side by
# side, the decoder's mesh check, the components canonicalized side by side, the adjacency built on two
# threads; and how those threads start and are waited for (src/beside.h).
# Only these run: the rest of the suite is single-threaded and already ran twice. The corpus-wide split
# sweep is left out (a minute under TSAN; the crafted texts and mutants take the same two-thread path).
tsan_tests='ReadObjParallel.*:WriteTextParallel.*:Geometry.CoderThreadGivesTheSameBytes'
tsan_tests+=':Codec.BestKeepsTheSmallestPartition:Codec.ThreadedPathsGiveTheMeshBack'
tsan_tests+=':Canonical.TwoThreadsGiveTheSameForm:Adjacency.*:ReadObjMeshParallel.*:Beside.*'
tsan_tests+='-ReadObjParallel.EveryCorpusObjReadsTheSameAtManySplits'
tsan_tests+=':ReadObjMeshParallel.EveryCorpusObjReadsTheSameAtManySplits'
if ((run_tsan)); then
  log "threaded-seam tests under ThreadSanitizer (build-tsan)"
  start=$SECONDS
  cmake -S . -B build-tsan "${sanitized[@]}" -DQSP_TSAN=ON >/dev/null
  cmake --build build-tsan --target qsp_seam_tests -j"$jobs"
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 build-tsan/qsp_seam_tests --gtest_filter="$tsan_tests"
  echo "hardening: threaded seams passed under ThreadSanitizer in $((SECONDS - start)) s"
fi

if ((run_fuzz)); then
  log "fuzzers (build-fuzz, ${fuzz_time} s per target)"
  start=$SECONDS
  cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
    -DQSP_FUZZ=ON -DQSP_BUILD_TESTS=OFF -DQSP_WERROR=OFF >/dev/null
  cmake --build build-fuzz --target qsp_fuzz -j"$jobs"
  run=build-fuzz/run
  rm -rf "$run/seeds" "$run/logs" "$run/artifacts"
  mkdir -p "$run/logs" "$run/artifacts"
  build-fuzz/fuzz/qsp_fuzz_seeds "$run/seeds" testdata "$shared"

  # QSP_FUZZ_TARGETS="read_mesh" runs only those (names without fuzz_); a target with an open finding
  # (testdata/known-findings/) leaves this list until it is fixed.
  targets=(${QSP_FUZZ_TARGETS:-decode_qsp roundtrip read_obj read_off read_ply read_mesh submesh})
  declare -A max_len=([decode_qsp]=32768 [roundtrip]=16384 [read_obj]=16384 [read_off]=16384 [read_ply]=16384
    [read_mesh]=16384 [submesh]=4096)
  declare -A dict=([decode_qsp]=qsp [roundtrip]=mesh [read_obj]=mesh [read_off]=mesh [read_ply]=ply
    [read_mesh]=mesh)
  # fuzz_read_mesh sniffs the format, so the three readers' seed folders serve it.
  declare -A seeds=([read_mesh]="read_obj read_off read_ply")
  fuzz_one() {
    local t=$1 s dirs=()
    for s in ${seeds[$t]:-$t}; do dirs+=("$run/seeds/$s"); done
    # The corpus grows across runs (build output, never committed); seeds and the regression files
    # in testdata/invalid/fuzz are read every time.
    mkdir -p "$run/corpus/$t"
    "build-fuzz/fuzz/fuzz_$t" "$run/corpus/$t" "${dirs[@]}" testdata/invalid/fuzz \
      -max_total_time="$fuzz_time" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 \
      -malloc_limit_mb=1024 -print_final_stats=1 -artifact_prefix="$run/artifacts/$t-" \
      ${dict[$t]:+-dict="fuzz/${dict[$t]}.dict"} \
      >"$run/logs/$t.log" 2>&1
  }
  declare -A pid
  failed=()
  running=0
  for t in "${targets[@]}"; do
    if ((running >= ${QSP_FUZZ_JOBS:-$jobs})); then
      wait -n || true
      running=$((running - 1))
    fi
    fuzz_one "$t" &
    pid[$t]=$!
    running=$((running + 1))
  done
  for t in "${targets[@]}"; do
    if ! wait "${pid[$t]}"; then failed+=("$t"); fi
  done
  printf '\n%-12s %14s %10s %8s\n' target executions exec/s corpus
  for t in "${targets[@]}"; do
    execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$run/logs/$t.log" | tail -1)
    speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$run/logs/$t.log" | tail -1)
    corpus=$(find "$run/corpus/$t" -type f | wc -l)
    printf '%-12s %14s %10s %8s\n' "$t" "${execs:-?}" "${speed:-?}" "$corpus"
  done
  if ((${#failed[@]})); then
    for t in "${failed[@]}"; do
      echo
      echo "hardening: fuzz_$t found a problem; last lines of $run/logs/$t.log:"
      grep -v '^#' "$run/logs/$t.log" | tail -40
    done
    ls -l "$run/artifacts" >&2
    echo "hardening: FAILED (${failed[*]})" >&2
    exit 1
  fi
  echo "hardening: fuzzers found nothing in $((SECONDS - start)) s"
fi
echo "hardening: OK"
