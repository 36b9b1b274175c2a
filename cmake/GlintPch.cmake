# Precompiled headers for the targets whose sources all parse the same heavy headers: GoogleTest
# and nlohmann/json in the unit tests, CLI11 and nlohmann/json in the command-line tools. Each
# header is then parsed once per build instead of once per source, which shortens both builds of
# .ci/run (make test, make test-sanitize) on 2 cores (docs/architecture.md, "Build time"). The
# first target of each kind builds the header; the others reuse it (REUSE_FROM: every Glint
# target compiles with the same flags, and the definitions that differ between them do not
# appear in these headers). The sources still include what they use; configure with
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON to build without (checks that they do).

# glint_shared_pch(kind target headers...): `target` reuses the precompiled header of the first
# target of `kind`, or builds it from `headers` if it is the first.
function(glint_shared_pch kind target)
  get_property(first GLOBAL PROPERTY GLINT_PCH_${kind})
  if(first)
    target_precompile_headers(${target} REUSE_FROM ${first})
  else()
    target_precompile_headers(${target} PRIVATE ${ARGN})
    set_property(GLOBAL PROPERTY GLINT_PCH_${kind} ${target})
  endif()
endfunction()

# glint_test_pch(target): a GoogleTest executable.
function(glint_test_pch target)
  glint_shared_pch(test ${target} <gtest/gtest.h> <nlohmann/json.hpp>)
endfunction()

# glint_cli_pch(target): a command-line tool built on CLI11.
function(glint_cli_pch target)
  glint_shared_pch(cli ${target} <CLI/CLI.hpp> <nlohmann/json.hpp>)
endfunction()
