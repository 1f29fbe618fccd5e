# Tests of pipeline/hdf5 (owner: io).
fogpipe_add_test(NAME hdf5_wrappers_test
  SOURCES ${CMAKE_CURRENT_LIST_DIR}/hdf5/file_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/hdf5/atomic_output_file_test.cpp
          ${CMAKE_CURRENT_LIST_DIR}/io/test_recording_files.cpp
  LIBS fogpipe::pipeline)
