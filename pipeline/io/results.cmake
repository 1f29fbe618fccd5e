# Results file layout (schemas/results-v1.*) and provenance hashing; owned by the graph part.
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/results_reader.cpp
  ${CMAKE_CURRENT_LIST_DIR}/results_writer.cpp
  ${CMAKE_CURRENT_LIST_DIR}/sha256.cpp)
