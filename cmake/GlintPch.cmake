# Precompiled headers for the targets whose sources all parse the same heavy headers: GoogleTest
# and nlohmann/json in the unit tests, CLI11 and nlohmann/json in the command-line tools. Each
# header is then parsed once per build instead of once per source, which shortens both builds of
# .ci/run (make test, make test-sanitize) on 2 cores (docs/architecture.md, "Build time"). One
# object library per kind builds the header and every target of that kind reuses it
# (REUSE_FROM: every Glint target compiles with the same flags). The sources still include what
# they use; configure with -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON to build without (checks that
# they do).

# glint_shared_pch(kind target libraries -- headers...): `target` reuses the precompiled header
# of `kind`, built once by the object library glint_<kind>_pch from `headers`, with the include
# paths and definitions of `libraries` only. GCC refuses a precompiled header where a macro
# defined when it was built is not defined, so it is built with no definitions of Glint's own.
function(glint_shared_pch kind target)
  set(creator glint_${kind}_pch)
  if(NOT TARGET ${creator})
    list(FIND ARGN -- split)
    list(SUBLIST ARGN 0 ${split} libraries)
    math(EXPR first "${split} + 1")
    list(SUBLIST ARGN ${first} -1 headers)
    set(source ${CMAKE_BINARY_DIR}/pch/${creator}.cpp)
    file(CONFIGURE OUTPUT ${source}
         CONTENT "// Builds the ${kind} precompiled header (cmake/GlintPch.cmake).\n")
    add_library(${creator} OBJECT ${source})
    target_link_libraries(${creator} PRIVATE ${libraries})
    glint_warnings(${creator})
    target_precompile_headers(${creator} PRIVATE ${headers})
  endif()
  target_precompile_headers(${target} REUSE_FROM ${creator})
endfunction()

# glint_test_pch(target): a GoogleTest executable.
function(glint_test_pch target)
  glint_shared_pch(test ${target} GTest::gtest nlohmann_json::nlohmann_json
                   -- <gtest/gtest.h> <nlohmann/json.hpp>)
endfunction()

# glint_cli_pch(target): a command-line tool built on CLI11.
function(glint_cli_pch target)
  glint_shared_pch(cli ${target} CLI11::CLI11 nlohmann_json::nlohmann_json
                   -- <CLI/CLI.hpp> <nlohmann/json.hpp>)
endfunction()
