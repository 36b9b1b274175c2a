// The replay of tests/data/fuzz-regressions/TARGET/ through a harness (fuzz_targets.h,
// denoise_fuzz_targets.h), for the GoogleTest suites that keep the fuzzers' findings fixed
// (FuzzRegressions.* in integration_tests, DenoiseFuzzRegressions.* in denoise_tests).
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace glint::fuzz {

/// The bytes of the file at `path`.
inline std::vector<std::uint8_t> readBytes(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// The files of tests/fuzz/seeds/`target`/ (a target's seeds); fails the test when there are none.
inline std::vector<std::filesystem::path> seedFiles(const char* target) {
    const std::filesystem::path dir =
        std::filesystem::path(GLINT_SOURCE_DIR) / "tests/fuzz/seeds" / target;
    std::vector<std::filesystem::path> out;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) out.push_back(entry.path());
    EXPECT_FALSE(out.empty()) << "no seeds in " << dir;
    return out;
}

/// Runs every file of tests/data/fuzz-regressions/`target`/ (README.md left out) through `run`,
/// which aborts the test binary on a bug; fails when the folder holds none.
inline void replay(const char* target, void (*run)(const std::uint8_t*, std::size_t)) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(GLINT_SOURCE_DIR) / "tests/data/fuzz-regressions" / target;
    ASSERT_TRUE(fs::is_directory(dir)) << dir;
    int files = 0;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (!entry.is_regular_file() || entry.path().filename() == "README.md") continue;
        const std::vector<std::uint8_t> bytes = readBytes(entry.path());
        SCOPED_TRACE(entry.path().string());
        run(bytes.data(), bytes.size());
        ++files;
    }
    EXPECT_GT(files, 0) << "no regression inputs in " << dir;
}

}  // namespace glint::fuzz
