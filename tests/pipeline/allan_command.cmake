# Tests of `fogpipe allan` (owner: io).
fogpipe_add_test(NAME cli_allan_command_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/allan_command_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
target_compile_definitions(cli_allan_command_test PRIVATE FOGPIPE_BINARY="$<TARGET_FILE:fogpipe>")
add_dependencies(cli_allan_command_test fogpipe)

# Independent numpy check on the real recording (not committed; ../shared beside the clone).
# Debian's python3 (numpy, h5py), not a pyenv one that may come first on PATH.
find_program(FOGPIPE_SYSTEM_PYTHON3 python3 PATHS /usr/bin NO_DEFAULT_PATH)
if(FOGPIPE_SYSTEM_PYTHON3)
  add_test(NAME AllanCommand.AgreesWithAnIndependentNumpyCumulativeSumOnTheRealRecording
    COMMAND ${FOGPIPE_SYSTEM_PYTHON3} ${CMAKE_CURRENT_LIST_DIR}/cli/allan_command_check.py
            --fogpipe $<TARGET_FILE:fogpipe>
            --data ${PROJECT_SOURCE_DIR}/../shared/data/real-imu
            --data /work/shared/data/real-imu)
  set_tests_properties(AllanCommand.AgreesWithAnIndependentNumpyCumulativeSumOnTheRealRecording
    PROPERTIES SKIP_RETURN_CODE 77 LABELS unit TIMEOUT 120)
endif()
