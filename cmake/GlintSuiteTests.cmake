# Run by ctest (a TEST_INCLUDE_FILES script, cmake/GlintTests.cmake): adds one test per
# GoogleTest suite of GLINT_SUITES_BINARY, "Suite.*@binary" running --gtest_filter=Suite.*.
get_filename_component(binary_name "${GLINT_SUITES_BINARY}" NAME)
if(NOT EXISTS "${GLINT_SUITES_BINARY}")
  add_test("${binary_name}_NOT_BUILT" "${binary_name}_NOT_BUILT")
  return()
endif()
execute_process(COMMAND "${GLINT_SUITES_BINARY}" --gtest_list_tests
                OUTPUT_VARIABLE listing RESULT_VARIABLE status TIMEOUT 60)
if(NOT status EQUAL 0)
  add_test("${binary_name}_NOT_LISTED" "${binary_name}_NOT_LISTED")
  return()
endif()
string(REPLACE "\n" ";" lines "${listing}")
foreach(line IN LISTS lines)
  # A suite's line starts in column 0 ("Suite." or "Prefix/Suite.  # TypeParam = …"); its tests
  # are indented.
  if(line MATCHES "^([^ ]+)\\.")
    set(suite "${CMAKE_MATCH_1}")
    add_test("${suite}.*@${binary_name}" "${GLINT_SUITES_BINARY}" "--gtest_filter=${suite}.*")
    set_tests_properties("${suite}.*@${binary_name}" PROPERTIES
                         WORKING_DIRECTORY "${GLINT_SUITES_WORKING_DIRECTORY}")
  endif()
endforeach()
