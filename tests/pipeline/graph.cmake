# Tests of pipeline/graph, the results layout (pipeline/io/results_*) and the run/info commands.
fogpipe_add_test(NAME graph_sha256_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/sha256_test.cpp LIBS fogpipe::pipeline)
fogpipe_add_test(NAME graph_run_config_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/run_config_test.cpp LIBS fogpipe::pipeline)
fogpipe_add_test(NAME graph_inputs_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/inputs_test.cpp LIBS fogpipe::pipeline)
fogpipe_add_test(NAME graph_status_log_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/status_log_test.cpp LIBS fogpipe::pipeline)
# End-to-end through the binary (tests/pipeline/cli/run_campaign_test.py; Debian python3-h5py).
add_test(NAME graph_run_campaign_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/run_campaign_test.py
          $<TARGET_FILE:fogpipe> ${PROJECT_SOURCE_DIR} campaign threads config dryrun resume
          identity)
add_test(NAME graph_run_sigterm_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/run_campaign_test.py
          $<TARGET_FILE:fogpipe> ${PROJECT_SOURCE_DIR} sigterm sigterm_fast)
add_test(NAME graph_run_sigkill_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/run_campaign_test.py
          $<TARGET_FILE:fogpipe> ${PROJECT_SOURCE_DIR} sigkill)
set_tests_properties(graph_run_campaign_test PROPERTIES LABELS "integration" TIMEOUT 600)
set_tests_properties(graph_run_sigterm_test graph_run_sigkill_test PROPERTIES
  LABELS "integration;slow" TIMEOUT 900)
