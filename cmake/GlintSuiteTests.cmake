# Run by ctest (a TEST_INCLUDE_FILES script, cmake/GlintTests.cmake): adds one test per
# GoogleTest suite of GLINT_SUITES_BINARY, "Suite.*@binary" running --gtest_filter=Suite.* in
# GLINT_SUITES_WORKING_DIRECTORY, with the properties GLINT_SUITES_PROPERTIES (name value ...).
# A failing suite's output (printed by ctest --output-on-failure) names each failing test in
# GoogleTest's "[  FAILED  ] Suite.Test" lines.
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

# Registers `suite` with `count` tests that are not DISABLED_.
function(glint_add_suite_test suite count)
  set(name "${suite}.*@${binary_name}")
  add_test("${name}" "${GLINT_SUITES_BINARY}" "--gtest_filter=${suite}.*")
  # Skipped only when every test of the suite skipped: GoogleTest's summary then counts them all
  # ("[  SKIPPED ] 1 test, listed below" or "N tests, …"). A skip regex matching any skip would
  # report a suite with one skipped and one failing test as skipped, not failed.
  if(count EQUAL 1)
    set(skipped "\\[  SKIPPED \\] 1 test, listed below")
  else()
    set(skipped "\\[  SKIPPED \\] ${count} tests, listed below")
  endif()
  set_tests_properties("${name}" PROPERTIES WORKING_DIRECTORY "${GLINT_SUITES_WORKING_DIRECTORY}"
                                            SKIP_REGULAR_EXPRESSION "${skipped}")
  if(count EQUAL 0)
    set_tests_properties("${name}" PROPERTIES DISABLED TRUE)
  endif()
  if(GLINT_SUITES_PROPERTIES)
    set_tests_properties("${name}" PROPERTIES ${GLINT_SUITES_PROPERTIES})
  endif()
endfunction()

# A value parameter's printout may hold ";", "[" or "]", which would split or join list items.
string(REGEX REPLACE "[][;]" "_" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")
set(suite "")
foreach(line IN LISTS lines)
  # A suite's line starts in column 0 ("Suite." or "Prefix/Suite.  # TypeParam = …"); its tests
  # are indented ("  Test" or "  Test/0  # GetParam() = …").
  if(line MATCHES "^([^ ]+)\\.")
    if(NOT suite STREQUAL "")
      glint_add_suite_test("${suite}" ${count})
    endif()
    set(suite "${CMAKE_MATCH_1}")
    set(count 0)
  elseif(NOT suite STREQUAL "" AND line MATCHES "^  [^ ]" AND NOT line MATCHES "^  DISABLED_"
         AND NOT suite MATCHES "(^|/)DISABLED_")
    math(EXPR count "${count} + 1")
  endif()
endforeach()
if(NOT suite STREQUAL "")
  glint_add_suite_test("${suite}" ${count})
endif()
