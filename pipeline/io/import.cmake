# `fogpipe import`: text and MATLAB v7.3 sources read into contract-v1 recordings (owner: import).
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/recording_import.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/text_import.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/matlab_import.cpp)
