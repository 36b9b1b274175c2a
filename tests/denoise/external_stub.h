// The stand-in external denoiser (external_denoiser_stub.cpp) as the external tests run it: its
// path, the external filter's parameters that run it, and a fixture giving each test its own
// TMPDIR (where the filter makes its private folder) and a fresh list of allowed commands
// holding the stub.
#pragma once

#include <gtest/gtest.h>

#include <stdlib.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "glint/denoise/external.h"
#include "glint/denoise/filter.h"

namespace glint::denoise::testing {

/// The stub, built beside the test binary.
inline std::filesystem::path stubPath() {
    return std::filesystem::read_symlink("/proc/self/exe").parent_path() / "external_denoiser_stub";
}

/// The stub's argv in `mode` on files of `format` ("exr" or "pfm"), creating `marker` when
/// given.
inline std::vector<std::string> stubCommand(const std::string& mode,
                                            const std::string& format = "exr",
                                            const std::string& marker = {}) {
    std::vector<std::string> argv{stubPath().string(), mode, format, "{color}", "{output}"};
    if (!marker.empty()) argv.push_back(marker);
    return argv;
}

/// The external filter's parameters running the stub in `mode` on files of `format`.
inline ParamValues stubParams(const std::string& mode, const std::string& format = "exr",
                              const std::string& marker = {}, double timeout = 600.0) {
    ParamValues p{{"format", format == "pfm" ? 1.0 : 0.0}, {"timeout", timeout}};
    p.strings["command"] = stubCommand(mode, format, marker);
    return p;
}

/// Each test in its own folder m_dir, with TMPDIR at m_dir/tmp and only the stub allowed.
class ExternalSandbox : public ::testing::Test {
  protected:
    void SetUp() override {
        namespace fs = std::filesystem;
        m_dir = fs::temp_directory_path() /
                ("external_test_" + std::to_string(::getpid()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(m_dir);
        fs::create_directories(m_dir / "tmp");
        if (const char* old = std::getenv("TMPDIR")) m_oldTmp = old;
        ::setenv("TMPDIR", (m_dir / "tmp").c_str(), 1);
        clearAllowedCommands();
        allowCommand(stubPath());
        ASSERT_TRUE(fs::exists(stubPath())) << stubPath();
    }
    void TearDown() override {
        if (m_oldTmp.empty())
            ::unsetenv("TMPDIR");
        else
            ::setenv("TMPDIR", m_oldTmp.c_str(), 1);
        clearAllowedCommands();
        std::filesystem::remove_all(m_dir);
    }
    /// True when the filter left nothing in TMPDIR.
    bool temporaryFolderEmpty() const { return std::filesystem::is_empty(m_dir / "tmp"); }

    std::filesystem::path m_dir;
    std::string m_oldTmp;
};

}  // namespace glint::denoise::testing
