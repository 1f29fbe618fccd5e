# Results file layout (schemas/results-v1.*) and provenance hashing; owned by the graph part.
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/column_datasets.cpp
  ${CMAKE_CURRENT_LIST_DIR}/results_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/results_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sha256.cpp)
# column_datasets.cpp compresses HDF5 chunks itself (zlib: Debian zlib1g-dev, a dependency of
# libhdf5-dev).
find_package(ZLIB REQUIRED)
target_link_libraries(fogpipe_pipeline PRIVATE ZLIB::ZLIB)
