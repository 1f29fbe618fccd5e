# Campaign manifest and shards (fogpipe plan), and the merged campaign table (fogpipe merge).
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/campaign_manifest.cpp
  ${CMAKE_CURRENT_LIST_DIR}/campaign_table.cpp)
