# Reference filters' speed on a 24 h, 100 Hz record (8.64e6 samples), tuning included.
fogpipe_add_benchmark(NAME filters_benchmark SOURCES filters_benchmark.cpp LIBS fogpipe::algorithms)
