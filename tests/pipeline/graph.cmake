# Tests of pipeline/graph, the results layout (pipeline/io/results_*) and the run/info commands.
fogpipe_add_test(NAME graph_sha256_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/sha256_test.cpp LIBS fogpipe::pipeline)
fogpipe_add_test(NAME graph_inputs_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/inputs_test.cpp LIBS fogpipe::pipeline)
