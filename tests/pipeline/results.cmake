# Tests of the results files' large datasets (pipeline/io/column_datasets), the memory budget
# (pipeline/graph/memory_budget) and the independent h5py check of results files
# (scripts/check_results_h5py.py) on every storage option; owner: scale.
fogpipe_add_test(NAME io_column_datasets_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/column_datasets_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
fogpipe_add_test(NAME graph_memory_budget_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/memory_budget_test.cpp LIBS fogpipe::pipeline)
# Through the binary with Debian's python3-h5py: every storage option passes the h5py check,
# corrupted copies fail it, and the memory budget is kept (peak RSS) or refused with a message.
add_test(NAME results_check_h5py_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/results_check_test.py
          $<TARGET_FILE:fogpipe> ${PROJECT_SOURCE_DIR})
set_tests_properties(results_check_h5py_test PROPERTIES LABELS "integration" TIMEOUT 600)
