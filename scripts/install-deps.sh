#!/usr/bin/env bash
# Installs everything fogpipe needs to build, test and plot, from Debian 12 packages only.
# --test adds what only the tests need: chromium, which renders the campaign HTML report headless.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
PACKAGES=(
  build-essential cmake git pkg-config
  libeigen3-dev libhdf5-dev hdf5-tools libtbb-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev libboost-dev
  nlohmann-json3-dev libtomlplusplus-dev libssl-dev
  python3 python3-numpy python3-h5py python3-matplotlib
)
if [ "${1:-}" = "--test" ]; then PACKAGES+=(chromium); fi
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "fogpipe: installing ${missing[*]}" >&2
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
