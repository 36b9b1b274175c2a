# Registers a GoogleTest binary with ctest (issue 47, "make test no slower"): one ctest per test
# (gtest_discover_tests, the default), or with GLINT_CTEST_PER_SUITE=ON one ctest per suite,
# named "Suite.*@binary" and running --gtest_filter=Suite.*. A process start costs about 0.3 s of
# CPU here, nearly all of it the dynamic loader binding the ~260 libraries Debian's OpenImageIO
# pulls in (measured: the 80 image tests take 37 s one process each, 13 s in one process), so
# per suite make test starts about 170 processes instead of about 800.
option(GLINT_CTEST_PER_SUITE "one ctest per GoogleTest suite instead of one per test" OFF)

function(glint_discover_tests target)
  if(NOT GLINT_CTEST_PER_SUITE)
    gtest_discover_tests(${target} WORKING_DIRECTORY ${CMAKE_SOURCE_DIR} DISCOVERY_TIMEOUT 60)
    return()
  endif()
  # Listed when ctest runs (the binary as built then), as gtest_discover_tests' PRE_TEST mode.
  set(include_file "${CMAKE_CURRENT_BINARY_DIR}/${target}_suites.cmake")
  file(GENERATE OUTPUT "${include_file}" CONTENT
"set(GLINT_SUITES_BINARY \"$<TARGET_FILE:${target}>\")
set(GLINT_SUITES_WORKING_DIRECTORY \"${CMAKE_SOURCE_DIR}\")
include(\"${PROJECT_SOURCE_DIR}/cmake/GlintSuiteTests.cmake\")
")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${include_file}")
endfunction()
