# Speed of the model comparison (targets: 6 h at 10 Hz <= 2 s; 24 h at 100 Hz <= 30 s
# with 2 threads). BM_Compare is single-threaded; BM_CompareTwoThreads runs the trial fits on two
# threads like the CLI does on oneTBB.
find_package(Threads REQUIRED)
fogpipe_add_benchmark(NAME compare_benchmark
                      SOURCES ${CMAKE_CURRENT_LIST_DIR}/compare_benchmark.cpp
                      LIBS fogpipe::algorithms Threads::Threads)
