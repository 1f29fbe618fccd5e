# The Debian package (cmake/packaging.cmake) built with CPack and checked: contents, Depends against
# the linked libraries, and the unpacked binary finding its installed schemas. Exit 77 is a skip.
add_test(NAME package_deb_test
  COMMAND bash ${CMAKE_CURRENT_LIST_DIR}/packaging/package_test.sh ${PROJECT_BINARY_DIR}
          ${PROJECT_SOURCE_DIR})
set_tests_properties(package_deb_test PROPERTIES
  LABELS "package;integration" TIMEOUT 300 SKIP_RETURN_CODE 77)
