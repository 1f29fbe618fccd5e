# fogpipe sweep: I/O around algorithms/method/sweep_* (owned by the sweep part).
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/sweep_runner.cpp)
