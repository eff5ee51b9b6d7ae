#!/usr/bin/env bash
# Installs what qsp needs to build and test, from Debian's packages. Idempotent; quick when all is there.
# Usage: tools/setup.sh [--bench]   (--bench adds the tools the comparison benchmarks run)
set -euo pipefail
pkgs=(cmake ninja-build g++ pkg-config libopenmesh-dev libcli11-dev libzstd-dev libxxhash-dev zlib1g-dev
      libgtest-dev libgmock-dev libbenchmark-dev python3)
if [[ "${1:-}" == "--bench" ]]; then
  pkgs+=(draco libmeshoptimizer-dev bliss zstd xz-utils hyperfine time)
fi
if [[ "${QSP_WITH_CLANG:-0}" == "1" ]]; then  # tools/hardening.sh: the sanitized builds and the fuzzers
  pkgs+=(clang libclang-rt-14-dev)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
