# Results-file writing: one chunk of an IMF column encoded as HDF5's shuffle + deflate filters
# would store it (pipeline/io/column_datasets.h), float64 and float32, compressed and not.
fogpipe_add_benchmark(NAME column_datasets_benchmark SOURCES column_datasets_benchmark.cpp
  LIBS fogpipe::pipeline)
target_include_directories(column_datasets_benchmark PRIVATE ${PROJECT_SOURCE_DIR})
