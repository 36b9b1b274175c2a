# Precompiled headers for the targets whose many sources all parse the same heavy headers:
# GoogleTest and nlohmann/json in the unit tests, CLI11 and nlohmann/json in the command-line
# tools. Each header is then parsed once per target instead of once per source, which shortens
# both builds of .ci/run (make test, make test-sanitize) on 2 cores (docs/architecture.md,
# "Build time"). The sources still include what they use; configure with
# -DCMAKE_DISABLE_PRECOMPILE_HEADERS=ON to build without (checks that they do).

# glint_test_pch(target): a GoogleTest executable.
function(glint_test_pch target)
  target_precompile_headers(${target} PRIVATE <gtest/gtest.h> <nlohmann/json.hpp>)
endfunction()

# glint_cli_pch(target): a command-line tool of several sources built on CLI11.
function(glint_cli_pch target)
  target_precompile_headers(${target} PRIVATE
    <CLI/CLI.hpp> <nlohmann/json.hpp>)
endfunction()
