# `fogpipe run --model FILE` end to end through the binary (owner: imfview): simulate -> compare
# --save-model -> run with and without the model; failure cases and resume.
fogpipe_add_test(NAME run_model_test
                 SOURCES ${CMAKE_CURRENT_LIST_DIR}/cli/run_model_test.cpp
                 LIBS fogpipe::pipeline LABELS slow)
add_dependencies(run_model_test fogpipe)
target_compile_definitions(run_model_test PRIVATE FOGPIPE_BINARY="$<TARGET_FILE:fogpipe>")
