#!/usr/bin/env bash
# Installs the Debian 12 packages ARTEMIS builds, tests and runs with.
# Idempotent: packages already present are left alone; safe to run again.
# Usage: scripts/install-deps.sh            (as root, or with sudo available)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config ccache git
  clang-format clang-tidy
  # core dependencies (DESIGN.md)
  libeigen3-dev libtbb-dev libcgal-dev libembree-dev libnanoflann-dev
  libstb-dev libpng-dev libtinygltf-dev libcli11-dev libspdlog-dev libfmt-dev
  nlohmann-json3-dev libcpp-httplib-dev wordnet-dev wordnet-base
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # interoperability checks (tests load our files with Open3D)
  python3 python3-numpy python3-open3d
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"
