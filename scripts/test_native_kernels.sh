#!/usr/bin/env bash
# The kernel suites (fogpipe_add_test(... KERNEL) in tests/: fixed-order, side-by-side and fused
# kernels against their scalar references) on the native build, -DFOGPIPE_NATIVE=ON: the build
# machine's instruction set, with FMA and AVX where it has them. The default (portable) build checks
# the same suites on the x86-64 baseline in ctest. Algorithms layer only, into
# ${NATIVE_BUILD_DIR:-build-native}.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${NATIVE_BUILD_DIR:-build-native}"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DFOGPIPE_NATIVE=ON \
  -DFOGPIPE_BUILD_PIPELINE=OFF -DFOGPIPE_BUILD_BENCHMARKS=OFF "$@" >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)" --target kernel_tests
# Only the kernel_tests target is built: every other suite is a <target>_NOT_BUILT placeholder.
ctest --test-dir "$BUILD_DIR" -E '_NOT_BUILT$' --output-on-failure -j"$(nproc)"
