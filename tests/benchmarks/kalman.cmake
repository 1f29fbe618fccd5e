# Steady-state AR Kalman filtering speed (target: <= 5 ns per sample for p <= 6).
fogpipe_add_benchmark(NAME kalman_benchmark SOURCES kalman_benchmark.cpp LIBS fogpipe::algorithms)
