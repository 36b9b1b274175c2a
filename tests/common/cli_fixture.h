// A GoogleTest fixture for end-to-end CLI tests: runs a Glint binary built beside the test binary
// (build/bin/) with stdout and stderr captured, inside a fresh per-test temporary directory.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

namespace glint::testing {

/// What one run of a CLI did.
struct RunResult {
    int exitCode = -1;
    std::string out;
    std::string err;
};

/// Whole contents of a text file ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Fixture for the CLI named by the derived class's constructor argument.
class CliFixture : public ::testing::Test {
  protected:
    explicit CliFixture(std::string binaryName) : m_name(std::move(binaryName)) {}

    void SetUp() override {
        namespace fs = std::filesystem;
        m_binary = fs::read_symlink("/proc/self/exe").parent_path() / m_name;
        ASSERT_TRUE(fs::exists(m_binary))
            << m_name << " must be built next to the test: " << m_binary;
        m_dir = fs::temp_directory_path() /
                (m_name + "_cli_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
    }
    void TearDown() override {
        if (!m_dir.empty()) std::filesystem::remove_all(m_dir);
    }

    /// Runs `binary args` through the shell (args are not quoted: keep paths free of spaces).
    RunResult run(const std::string& args) const { return run({}, args); }

    /// The same with environment assignments (e.g. "GLINT_MEMORY_LIMIT=1M") before the binary.
    RunResult run(const std::string& env, const std::string& args) const {
        return runBinary(m_binary, env, args);
    }

    /// Runs another Glint binary built beside the test (e.g. glint-denoise's bank for a test of
    /// glint-lab), the same way.
    RunResult runTool(const std::string& name, const std::string& args) const {
        return runBinary(m_binary.parent_path() / name, {}, args);
    }

    /// Runs `args` through glint-lab when it starts with one of glint-lab's subcommands (oracle,
    /// navigate, auto: glint-denoise's auto with every tuning flag), else through this fixture's
    /// binary: for the tests of auto's tuning and of tables of cases over several commands.
    RunResult runEither(const std::string& args) const { return runEither({}, args); }

    /// The same with environment assignments.
    RunResult runEither(const std::string& env, const std::string& args) const {
        for (const char* lab : {"oracle ", "navigate ", "auto "})
            if (args.rfind(lab, 0) == 0)
                return runBinary(m_binary.parent_path() / "glint-lab", env, args);
        return run(env, args);
    }

    /// Path of `name` inside the test's temporary directory.
    std::string path(const std::string& name) const { return (m_dir / name).string(); }

    std::string m_name;
    std::filesystem::path m_binary;
    std::filesystem::path m_dir;

  private:
    RunResult runBinary(const std::filesystem::path& binary, const std::string& env,
                        const std::string& args) const {
        const std::filesystem::path out = m_dir / "stdout.txt", err = m_dir / "stderr.txt";
        const std::string cmd = (env.empty() ? "" : env + " ") + binary.string() + " " + args +
                                " >" + out.string() + " 2>" + err.string();
        const int status = std::system(cmd.c_str());
        RunResult r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(out);
        r.err = slurp(err);
        return r;
    }
};

}  // namespace glint::testing
