# CLI-level test of `fogpipe compare` (owner: compare): fogpipe simulate -> compare --json ->
# compare --add -> compare --history, through the real binary.
fogpipe_add_test(NAME compare_command_test
                 SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/compare_command_test.cpp
                 LIBS fogpipe::pipeline LABELS slow)
add_dependencies(compare_command_test fogpipe)
target_compile_definitions(compare_command_test PRIVATE FOGPIPE_BINARY="$<TARGET_FILE:fogpipe>")

# The model history round trip (pipeline/io/model_history.*, owner: compare).
fogpipe_add_test(NAME model_history_test
                 SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/model_history_test.cpp
                 LIBS fogpipe::pipeline)
