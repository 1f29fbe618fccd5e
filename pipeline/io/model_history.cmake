# Model file and model history of `fogpipe compare` (owner: compare).
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/model_history.cpp)
