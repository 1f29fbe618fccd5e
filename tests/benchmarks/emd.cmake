# EMD speed: 10 fixed sifts of 1e6 white-noise samples (target <= 1.5 s, one thread).
fogpipe_add_benchmark(NAME emd_benchmark SOURCES emd_benchmark.cpp LIBS fogpipe::algorithms)
target_compile_definitions(emd_benchmark PRIVATE FOGPIPE_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
target_include_directories(emd_benchmark PRIVATE ${PROJECT_SOURCE_DIR})
# With oneTBB (the pipeline's dependency), also the EMD with its sifts' envelope work on 2 threads.
find_package(TBB QUIET)
if(TBB_FOUND)
  target_link_libraries(emd_benchmark PRIVATE TBB::tbb)
  target_compile_definitions(emd_benchmark PRIVATE FOGPIPE_BENCHMARK_WITH_TBB)
endif()
