# Registers a GoogleTest binary with ctest (issue 47, "make test no slower"): one ctest per suite,
# named "Suite.*@binary" and running --gtest_filter=Suite.* (cmake/GlintSuiteTests.cmake), or
# with -DGLINT_CTEST_PER_TEST=ON one ctest per test (gtest_discover_tests). A process start costs
# about 0.3 s of CPU here in a test binary that links OpenImageIO (to write its test images),
# nearly all of it the dynamic loader binding the ~260 libraries it pulls in, so per suite make
# test starts about 180 processes instead of about 800 (docs/lab/ctest-registration.md).
#
#   glint_discover_tests(target [PROPERTIES name value ...])
#
# Every ctest of the binary runs in the source folder and gets the PROPERTIES given (TIMEOUT,
# LABELS, ENVIRONMENT, RESOURCE_LOCK, RUN_SERIAL, …) either way. A suite whose every test calls
# GTEST_SKIP is reported skipped; one skipped test beside a failing one still fails its suite.
set(GLINT_SUITE_TESTS_SCRIPT "${CMAKE_CURRENT_LIST_DIR}/GlintSuiteTests.cmake")
option(GLINT_CTEST_PER_TEST "one ctest per GoogleTest test instead of one per suite" OFF)

function(glint_discover_tests target)
  # PARSE_ARGV keeps a value's own semicolons (ENVIRONMENT "A=1;B=2") escaped as \;.
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "PROPERTIES")
  if(GLINT_CTEST_PER_TEST)
    gtest_discover_tests(${target} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} DISCOVERY_TIMEOUT 60
                         PROPERTIES ${arg_PROPERTIES})
    return()
  endif()
  # Each property word as a bracket argument with its own semicolons escaped again (foreach
  # undid that), so that the script's set_tests_properties splits the words only.
  set(properties "")
  foreach(word IN LISTS arg_PROPERTIES)
    string(REPLACE ";" "\\;" word "${word}")
    string(APPEND properties " [==[${word}]==]")
  endforeach()
  # Listed when ctest runs (the binary as built then), as gtest_discover_tests' PRE_TEST mode.
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  file(GENERATE OUTPUT "${include_file}" CONTENT
"set(GLINT_SUITES_BINARY \"$<TARGET_FILE:${target}>\")
set(GLINT_SUITES_WORKING_DIRECTORY \"${CMAKE_SOURCE_DIR}\")
set(GLINT_SUITES_PROPERTIES${properties})
include(\"${GLINT_SUITE_TESTS_SCRIPT}\")
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()
