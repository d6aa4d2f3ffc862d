#!/usr/bin/env bash
# Installs every build and run dependency from Debian's archive. Idempotent; nothing is
# downloaded at build or run time.
set -euo pipefail
# clang-16 and libclang-rt-16-dev (its sanitizer and libFuzzer runtimes) build the fuzz targets;
# Open MPI the release build's domain decomposition across ranks (the sanitizer build has none).
packages=(build-essential cmake ninja-build pkg-config libfmt-dev libcli11-dev nlohmann-json3-dev
          libtomlplusplus-dev zlib1g-dev libgtest-dev libbenchmark-dev python3 python3-matplotlib python3-numpy
          clang-16 libclang-rt-16-dev openmpi-bin libopenmpi-dev)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo_cmd=""; [[ $(id -u) -ne 0 ]] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
