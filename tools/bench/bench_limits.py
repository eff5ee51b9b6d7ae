#!/usr/bin/env python3
"""Peak memory and time of qsp decompress against the bounds of format-spec/qsp_format.md ("Limits and
memory"), measured here rather than in unit tests (CONTRIBUTING.md: never time anything in a unit test).

1. Valid files: the decoder's working memory stays below 128 V + 320 F bytes beyond the peak of
   `qsp --version`, plus the input file and the output text (meshes of testdata/, the largest shared
   mesh when ../shared is there, and a 700 x 600 patch of 421k vertices written here).
2. Refused files (testdata/invalid/qsp_*.qsp, among them files of a few dozen bytes declaring huge
   meshes; decompress refuses each): decompress and stats need no more memory than decompressing a 98-vertex cube plus 8 MiB,
   and under 2 s each.

Usage: tools/bench/bench_limits.py [QSP]   (default build/qsp). Exits 1 if any bound is exceeded.
Peak RSS is the child's ru_maxrss, which counts this process's memory too (fork): every figure is
compared with a baseline spawned the same way.
"""
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
QSP = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "qsp")
SHARED = os.environ.get("QSP_SHARED_DIR", os.path.join(ROOT, "..", "shared"))
PER_VERTEX, PER_FACE = 128, 320


def run(*args):
    """(exit code, peak RSS in KiB, seconds) of `qsp ARGS`, output to /dev/null."""
    start = time.monotonic()
    with open(os.devnull, "wb") as null:
        pid = os.posix_spawn(QSP, [QSP, *args], os.environ,
                             file_actions=[(os.POSIX_SPAWN_OPEN, 1, os.devnull, os.O_WRONLY, 0),
                                           (os.POSIX_SPAWN_OPEN, 2, os.devnull, os.O_WRONLY, 0)])
        _, status, usage = os.wait4(pid, 0)
    return os.waitstatus_to_exitcode(status), usage.ru_maxrss, time.monotonic() - start


def main():
    failed = []
    work = tempfile.mkdtemp(prefix="qsp_bench_limits_")
    meshes = [os.path.join(ROOT, "testdata", m) for m in ("keenan_spot_quadrangulated.obj", "mh_fedora.obj")]
    big = os.path.join(SHARED, "meshes", "mh_female_generic_cc2.obj")
    if os.path.exists(big):
        meshes.append(big)
    grid = os.path.join(work, "grid.obj")
    with open(grid, "w") as g:  # one patch: almost no topology
        g.writelines(f"v {x} {y} 0\n" for y in range(601) for x in range(701))
        for y in range(600):
            for x in range(700):
                a = y * 701 + x + 1
                g.write(f"f {a} {a + 1} {a + 702} {a + 701}\n")
    meshes.append(grid)
    base = run("--version")
    print(f"{'mesh':40} {'V':>8} {'F':>8} {'peak KiB':>9} {'bound KiB':>9} {'B/vertex':>8}")
    for m in meshes:
        q, out = os.path.join(work, "m.qsp"), os.path.join(work, "m.obj")
        assert run("compress", "-f", "--positions-only", m, q)[0] == 0, m
        code, peak, _ = run("decompress", "-f", q, out)
        assert code == 0, m
        info = json.loads(subprocess.run([QSP, "stats", "--json", q], capture_output=True, check=True).stdout)
        v, f = info["mesh"]["vertices"], info["mesh"]["faces"]
        io = os.path.getsize(q) + os.path.getsize(out)
        bound = base[1] + (PER_VERTEX * v + PER_FACE * f + io) / 1024
        per_vertex = ((peak - base[1]) * 1024 - io) / v
        print(f"{os.path.basename(m):40} {v:8} {f:8} {peak:9} {bound:9.0f} {per_vertex:8.0f}")
        if peak >= bound:
            failed.append(f"{m}: peak {peak} KiB over the bound {bound:.0f} KiB")
    cube = os.path.join(ROOT, "testdata", "golden", "cube_4.qsp")
    ref = run("decompress", cube, "-")
    invalid = os.path.join(ROOT, "testdata", "invalid")
    worst_rss, worst_time = 0, 0.0
    for name in sorted(n for n in os.listdir(invalid) if n.startswith("qsp_") and n.endswith(".qsp")):
        for command in ("decompress", "stats"):
            args = [command, os.path.join(invalid, name)] + (["-"] if command == "decompress" else [])
            code, peak, seconds = run(*args)
            worst_rss, worst_time = max(worst_rss, peak - ref[1]), max(worst_time, seconds)
            if command == "decompress" and code != 1:  # stats reads no geometry: it may accept some
                failed.append(f"{command} {name}: exit {code}, expected 1")
            if peak >= ref[1] + 8 * 1024 or seconds >= 2.0:
                failed.append(f"{command} {name}: {peak} KiB (cube {ref[1]}), {seconds:.2f} s")
    print(f"refused files: at most {worst_rss} KiB over a cube's decompress, {worst_time:.3f} s")
    for f in failed:
        print("bench_limits: " + f, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
