#!/usr/bin/env bash
# The README's test command: installs dependencies, builds in Release (portable), runs the kernel
# suites on a native build (scripts/test_native_kernels.sh) and then every ctest suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --test
scripts/build.sh
scripts/test_native_kernels.sh
cd "${BUILD_DIR:-build}"
ctest --output-on-failure -j"$(nproc)" --timeout 1500 "$@"
