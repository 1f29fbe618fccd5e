# Tests of the sweep part: algorithms/method/sweep_*, pipeline/io/campaign_*, plan/merge/sweep CLI.
fogpipe_add_test(NAME sweep_evaluate_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/sweep_evaluate_test.cpp LIBS fogpipe::algorithms)
# A step, a ramp and a sinusoid of the input rate (deg/h): the truth moves within the record.
target_compile_definitions(sweep_evaluate_test PRIVATE
  SWEEP_TEST_RATE_PROFILE="step:300:20,ramp:900:1200:0.05,sine:0.005:10")
fogpipe_add_test(NAME sweep_campaign_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/graph/sweep_campaign_test.cpp LIBS fogpipe::pipeline)
# Through the binary: sweep table/CSV/plot/config, plan, merge idempotence and duplicates.
add_test(NAME sweep_cli_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/sweep_cli_test.py
          $<TARGET_FILE:fogpipe> ${PROJECT_SOURCE_DIR})
set_tests_properties(sweep_cli_test PROPERTIES LABELS "integration" TIMEOUT 300)
