#!/usr/bin/env bash
# Installs vpm's build and test dependencies from Debian 12 packages when any is missing.
# Idempotent and quiet: when everything is present it only runs dpkg-query (well under a second).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libopenvdb-dev libboost-iostreams-dev libblosc-dev libtbb-dev
  libembree-dev libopenexr-dev libimath-dev libeigen3-dev
  libgtest-dev libbenchmark-dev libnanoflann-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libpng-dev
  python3-matplotlib ccache
  pybind11-dev python3-dev python3-numpy python3-pytest   # the Python module (python/) and its tests
  slurm-wlm munge   # the Slurm split-render test (scripts/slurm/)
  python3-openvdb   # only to regenerate tests/data/vdb/puff.vdb (make_puff.py)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
