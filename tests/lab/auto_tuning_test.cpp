// glint-lab auto's tuning table: generated from the specs, and the one docs/lab/auto-tuning.md
// shows.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_fixture.h"

namespace glint::lab {
namespace {

namespace fs = std::filesystem;
using glint::testing::RunResult;

class LabAutoCli : public glint::testing::CliFixture {
  protected:
    LabAutoCli() : CliFixture("glint-lab") {}
};

TEST_F(LabAutoCli, TheDocsTuningTableIsTheOneTheSpecsGenerate) {
    // docs/lab/auto-tuning.md's table is `glint-lab auto --tuning-table`, verbatim: a spec
    // changed without the docs (or the reverse) fails here.
    const RunResult r = run("auto --tuning-table");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("| `--window` | `window` | 0 … 64 | 8 | 4 |"), std::string::npos) << r.out;
    std::ifstream in(fs::path(GLINT_SOURCE_DIR) / "docs/lab/auto-tuning.md");
    const std::string docs((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(docs.find(r.out), std::string::npos)
        << "docs/lab/auto-tuning.md lacks the generated table; paste this into it:\n"
        << r.out;
}

}  // namespace
}  // namespace glint::lab
