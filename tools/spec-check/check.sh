#!/usr/bin/env bash
# Decodes geometry sections with tools/spec-check/qspgeo.py, written from format-spec/qsp_format.md
# alone, and compares every coordinate bit for bit with the reference decoder: the golden files of the
# versions whose geometry it reads (revisions 4 and 5), and fresh encodes of testdata meshes and, when
# ../shared/meshes is there, of meshes that exercise chaining, repeats and layout order.
# Usage: check.sh QSP DUMP_STENCILS [PYTHON3]   (ctest runs it: "spec_decoder")
set -euo pipefail
qsp=$1 dump=$2 python=${3:-python3}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
files=("$root"/testdata/golden/*.qsp "$root"/testdata/golden/v1.3/*.qsp "$root"/testdata/golden/v2.0/*.qsp)
encode() {  # encode NAME MESH [OPTIONS...]: a fresh file to check
  local name=$1 mesh=$2
  shift 2
  [[ -f $mesh ]] || return 0
  "$qsp" compress -f --positions-only "$@" "$mesh" "$work/$name.qsp" >/dev/null
  files+=("$work/$name.qsp")
}
encode fedora "$root/testdata/mh_fedora.obj"                     # decimal grid, lossless
encode fedora_q14 "$root/testdata/mh_fedora.obj" --quantize 14
encode spot_q14 "$root/testdata/keenan_spot_quadrangulated.obj" --quantize 14
encode spot_q6 "$root/testdata/keenan_spot_quadrangulated.obj" --quantize 6
shared="$root/../shared/meshes"
encode gargoyle_q14 "$shared/quadriflow_gargoyle.obj" --quantize 14  # revision 5, normal chaining
encode horse "$shared/igl_horse_quad.obj"
encode pawn "$shared/osd_catmark_pawn.obj"                           # value repeats
encode xord "$shared/osd_catmark_xord_interior.obj"                  # layout order, exceptions
encode xord_q14 "$shared/osd_catmark_xord_interior.obj" --quantize 14
failed=0
for f in "${files[@]}"; do
  prefix="$work/$(basename "$f" .qsp)_$RANDOM"
  if ! "$dump" "$f" "$prefix" || ! "$python" "$here/qspgeo.py" "$f" "$prefix"; then
    echo "spec decoder disagrees: $f" >&2
    failed=1
  fi
done
echo "spec decoder: ${#files[@]} files checked"
exit $failed
