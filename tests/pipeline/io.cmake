# Tests of pipeline/io (owner: io).
fogpipe_add_test(NAME io_recording_reader_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/recording_reader_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/bad_input_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/missing_samples_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/schema_validator_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)

# `fogpipe validate` run as a program (exit codes, output).
fogpipe_add_test(NAME cli_validate_command_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/validate_command_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
target_compile_definitions(cli_validate_command_test PRIVATE FOGPIPE_BINARY="$<TARGET_FILE:fogpipe>")
add_dependencies(cli_validate_command_test fogpipe)

# The noise-term fit on real recordings that are not in the repository (skips when absent).
fogpipe_add_test(NAME io_noise_fit_real_data_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/noise_fit_real_data_test.cpp LIBS fogpipe::pipeline)

# `fogpipe import`: text and MATLAB v7.3 sources (owner: import).
fogpipe_add_test(NAME io_import_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/text_import_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/matlab_import_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
# End to end through the binary (tests/pipeline/cli/import_test.py; Debian python3-h5py).
add_test(NAME cli_import_test
  COMMAND /usr/bin/python3 ${PROJECT_SOURCE_DIR}/tests/pipeline/cli/import_test.py
          $<TARGET_FILE:fogpipe>)
set_tests_properties(cli_import_test PROPERTIES LABELS "integration" TIMEOUT 600)
