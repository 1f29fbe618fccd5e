# Tests of `fogpipe simulate` and of the contract-v1 recording writer it uses (owner: simulator).
fogpipe_add_test(NAME simulate_recording_writer_test
                 SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/simulate_recording_writer_test.cpp
                 LIBS fogpipe::pipeline)
fogpipe_add_test(NAME simulate_command_test
                 SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/simulate_command_test.cpp
                 LIBS fogpipe::pipeline)
# The command test runs the real binary.
add_dependencies(simulate_command_test fogpipe)
target_compile_definitions(simulate_command_test PRIVATE FOGPIPE_BINARY="$<TARGET_FILE:fogpipe>")
