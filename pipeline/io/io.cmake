# pipeline/io: recording reader, schema validator (owner: io). recording_writer.cmake and
# results.cmake are owned by the sim and graph helpers.
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/recording_error.cpp
  ${CMAKE_CURRENT_LIST_DIR}/missing_samples.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recording_reader.cpp)
