#Contract - v1 recording writer and truth sidecar(owner : simulator).
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR} / recording_writer.cpp)
