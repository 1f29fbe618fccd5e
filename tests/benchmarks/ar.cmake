# AR modelling benchmarks (algorithms/ar). Speed target: orders 1-20 with BIC on 1e6 samples <= 50 ms.
fogpipe_add_benchmark(NAME ar_benchmark SOURCES ${CMAKE_CURRENT_LIST_DIR}/ar_benchmark.cpp
                      LIBS fogpipe::algorithms)
