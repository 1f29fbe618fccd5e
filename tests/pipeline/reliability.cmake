# Hostile inputs, write errors, planted symlinks and overlapping runs, through the binary
# (tests/pipeline/reliability/*.py; Debian python3-h5py).
add_test(NAME reliability_hostile_inputs_test
  COMMAND /usr/bin/python3 ${CMAKE_CURRENT_LIST_DIR}/reliability/hostile_inputs_test.py
          $<TARGET_FILE:fogpipe> 3)
add_test(NAME reliability_fuzz_campaign_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/scripts/fuzz_campaign.py
          $<TARGET_FILE:fogpipe> 60 1)
set_tests_properties(reliability_hostile_inputs_test reliability_fuzz_campaign_test PROPERTIES
  LABELS "integration" TIMEOUT 900)
