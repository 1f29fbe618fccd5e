# Tests of pipeline/io (owner: io).
fogpipe_add_test(NAME io_recording_reader_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/io/recording_reader_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/bad_input_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/missing_samples_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
