# pipeline/hdf5: RAII wrappers over the HDF5 C++ API (owner: io).
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/hdf5_lock.cpp
  ${CMAKE_CURRENT_LIST_DIR}/error.cpp
  ${CMAKE_CURRENT_LIST_DIR}/string_io.cpp
  ${CMAKE_CURRENT_LIST_DIR}/object.cpp
  ${CMAKE_CURRENT_LIST_DIR}/dataset.cpp
  ${CMAKE_CURRENT_LIST_DIR}/group.cpp
  ${CMAKE_CURRENT_LIST_DIR}/file.cpp
  ${CMAKE_CURRENT_LIST_DIR}/atomic_output_file.cpp)
