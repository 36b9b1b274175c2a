#!/usr/bin/env bash
# ctest Tools.OneCtestPerSuiteKeepsPropertiesSkipsAndFailures: glint_discover_tests
# (cmake/GlintTests.cmake, cmake/GlintSuiteTests.cmake) on a stand-in GoogleTest binary (a shell
# script printing GoogleTest's listing and summaries) in a throw-away project, run by ctest.
# Checks: one ctest per suite named "Suite.*@binary"; the PROPERTIES given reach every suite
# (TIMEOUT, LABELS, a two-variable ENVIRONMENT) and it runs in the source folder; a suite whose
# every test skipped is reported skipped, while one skipped test beside a failing one fails its
# suite; the failing test is named in ctest --output-on-failure's output; a suite of DISABLED_
# tests only is disabled.
# Usage: suite_registration_test.sh SOURCE_DIR
set -euo pipefail
src=$(cd "$1" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; echo "--- ctest output:"; cat "$work/out.txt" 2>/dev/null || true; exit 1; }

cat >"$work/fake_tests" <<'EOF'
#!/usr/bin/env bash
summary() {  # passed skipped failed-names...
  echo "[  PASSED  ] $1 tests."
  [ "$2" = 0 ] || echo "[  SKIPPED ] $2 test$([ "$2" = 1 ] || echo s), listed below:"
}
case "$1" in
  --gtest_list_tests)
    printf 'Passing.\n  One\n  Two\nAllSkipped.\n  Skips\n  AlsoSkips\nSkipAndFail.\n  Skips\n  Fails\n'
    printf 'Values/Param.  # TypeParam = std::pair<int;[x>\n  Case/0  # GetParam() = [1;2\n'
    printf 'Env.\n  SeesItsProperties\nDisabled.\n  DISABLED_Off\n' ;;
  --gtest_filter=Passing.*) summary 2 0 ;;
  --gtest_filter=AllSkipped.*) summary 0 2; echo "[  SKIPPED ] AllSkipped.Skips" ;;
  --gtest_filter=SkipAndFail.*)
    summary 0 1
    echo "[  FAILED  ] 1 test, listed below:"
    echo "[  FAILED  ] SkipAndFail.Fails"
    exit 1 ;;
  --gtest_filter=Values/Param.*) summary 1 0 ;;
  --gtest_filter=Env.*)
    [ "${GLINT_A:-}" = 1 ] && [ "${GLINT_B:-}" = 2 ] && [ "$PWD" = "$GLINT_EXPECTED_DIR" ] ||
      { echo "[  FAILED  ] Env.SeesItsProperties: A=${GLINT_A:-} B=${GLINT_B:-} in $PWD"; exit 1; }
    summary 1 0 ;;
  *) echo "unexpected arguments: $*"; exit 3 ;;
esac
EOF
chmod +x "$work/fake_tests"

mkdir "$work/project"
cat >"$work/project/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.25)
project(suite_registration NONE)
enable_testing()
include("$src/cmake/GlintTests.cmake")
add_executable(fake_tests IMPORTED)
set_target_properties(fake_tests PROPERTIES IMPORTED_LOCATION "$work/fake_tests")
glint_discover_tests(fake_tests PROPERTIES TIMEOUT 30 LABELS fake
                     ENVIRONMENT "GLINT_A=1;GLINT_B=2;GLINT_EXPECTED_DIR=\${CMAKE_SOURCE_DIR}")
EOF
cmake -S "$work/project" -B "$work/build" -DGLINT_CTEST_PER_TEST=OFF >"$work/configure.txt" 2>&1 ||
  { cat "$work/configure.txt"; exit 1; }
cd "$work/build"
ctest --output-on-failure >"$work/out.txt" 2>&1 && fail "ctest passed although SkipAndFail fails"

passed() { grep -qE "Test +#[0-9]+: $1 \.+ +Passed" "$work/out.txt" || fail "$1 did not pass"; }
passed 'Passing\.\*@fake_tests'
passed 'Values/Param\.\*@fake_tests'
passed 'Env\.\*@fake_tests'
grep -qE 'AllSkipped\.\*@fake_tests \.+\*+Skipped' "$work/out.txt" || fail "AllSkipped not skipped"
grep -qE 'SkipAndFail\.\*@fake_tests \.+\*+Failed' "$work/out.txt" || fail "SkipAndFail not failed"
grep -qF '[  FAILED  ] SkipAndFail.Fails' "$work/out.txt" || fail "the failing test is not named"
grep -qE 'Disabled\.\*@fake_tests \.+\*+Not Run \(Disabled\)' "$work/out.txt" ||
  fail "Disabled not disabled"
[ "$(ctest -N | grep -c '@fake_tests')" = 6 ] || fail "not six ctests: $(ctest -N)"
ctest -N -L fake | grep -q 'Total Tests: 6' || fail "the label does not reach every suite"
ctest --show-only=json-v1 >"$work/tests.json"
grep -q '"name" : "TIMEOUT",' "$work/tests.json" && grep -q '"value" : 30' "$work/tests.json" ||
  fail "no TIMEOUT 30"
echo "ok: one ctest per suite, properties, skips, failures named"
