# pipeline/io: recording reader, schema validator (owner: io). recording_writer.cmake and
# results.cmake are owned by the sim and graph helpers.
target_sources(fogpipe_pipeline PRIVATE
  ${CMAKE_CURRENT_LIST_DIR}/recording_error.cpp
  ${CMAKE_CURRENT_LIST_DIR}/missing_samples.cpp
  ${CMAKE_CURRENT_LIST_DIR}/recording_reader.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/schema_validator.cpp)
# Where `fogpipe validate` looks for schema files after --schemas and $FOGPIPE_SCHEMAS_DIR: the
# installed schemas relative to the executable's folder, then (for a binary inside this build tree
# only) the source tree's schemas/ folder.
# (Source properties apply to targets of the named directory: fogpipe_pipeline lives in pipeline/.)
file(RELATIVE_PATH _fogpipe_schemas_from_bindir "${CMAKE_INSTALL_FULL_BINDIR}"
     "${CMAKE_INSTALL_PREFIX}/${FOGPIPE_INSTALL_SCHEMASDIR}")
set_source_files_properties(${CMAKE_CURRENT_LIST_DIR}/schema_validator.cpp
  DIRECTORY ${PROJECT_SOURCE_DIR}/pipeline PROPERTIES
  COMPILE_DEFINITIONS "FOGPIPE_SCHEMAS_FROM_BINDIR=\"${_fogpipe_schemas_from_bindir}\";FOGPIPE_BUILD_DIR=\"${PROJECT_BINARY_DIR}\";FOGPIPE_SCHEMAS_DIR=\"${PROJECT_SOURCE_DIR}/schemas\"")
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/file_validation.cpp)
# The recording layout is compiled in: the commands that read recordings check it without
# looking for schema files.
file(READ ${PROJECT_SOURCE_DIR}/schemas/recording-v1.json FOGPIPE_RECORDING_SCHEMA_JSON)
configure_file(${CMAKE_CURRENT_LIST_DIR}/recording_schema_text.cpp.in
  ${PROJECT_BINARY_DIR}/generated/recording_schema_text.cpp @ONLY)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/schemas/recording-v1.json)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/text_output_file.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/recording_check.cpp
  ${PROJECT_BINARY_DIR}/generated/recording_schema_text.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/allan_report.cpp)
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/noise_fit_report.cpp)
# Inputs inspected and read in child processes (a crash or hang in HDF5 stays in the child).
target_sources(fogpipe_pipeline PRIVATE ${CMAKE_CURRENT_LIST_DIR}/isolated_call.cpp
  ${CMAKE_CURRENT_LIST_DIR}/isolated_reader.cpp)
