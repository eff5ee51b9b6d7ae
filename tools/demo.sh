#!/usr/bin/env bash
# Builds qsp and runs its main job on a bundled mesh (the README's first command).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target qsp
mesh=testdata/keenan_spot_quadrangulated.obj
./build/qsp stats "$mesh"
