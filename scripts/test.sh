#!/usr/bin/env bash
# The README's test command: installs dependencies, builds in Release and runs every ctest suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test
scripts/build.sh
cd "${BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)" --timeout 1500 "$@"
