# Allan engine speed: OADEV of 1e7 samples at 64 log-spaced taus, with and without confidence
# intervals; ADEV / OHDEV / HDEV likewise. Run with --benchmark_repetitions=5.
fogpipe_add_benchmark(NAME allan_benchmark SOURCES allan_benchmark.cpp LIBS fogpipe::algorithms)
