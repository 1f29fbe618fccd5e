# Speed of the gyro simulator (owner: simulator). Not run by ctest.
fogpipe_add_benchmark(NAME simulation_benchmark
                      SOURCES ${CMAKE_CURRENT_LIST_DIR}/simulation_benchmark.cpp
                      LIBS fogpipe::algorithms)
