#!/usr/bin/env bash
# The kernel suites (fogpipe_add_test(... KERNEL) in tests/: fixed-order, side-by-side and fused
# kernels against their scalar references) on the portable build, -DFOGPIPE_NATIVE=OFF: x86-64
# baseline, no FMA, four-double lanes in two SSE registers. The default build checks the same
# suites natively. Algorithms layer only, into ${PORTABLE_BUILD_DIR:-build-portable}.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${PORTABLE_BUILD_DIR:-build-portable}"
cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DFOGPIPE_NATIVE=OFF \
  -DFOGPIPE_BUILD_PIPELINE=OFF -DFOGPIPE_BUILD_BENCHMARKS=OFF "$@" >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)" --target kernel_tests
# Only the kernel_tests target is built: every other suite is a <target>_NOT_BUILT placeholder.
ctest --test-dir "$BUILD_DIR" -E '_NOT_BUILT$' --output-on-failure -j"$(nproc)"
