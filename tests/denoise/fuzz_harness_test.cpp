// The denoise fuzz harnesses (tests/fuzz/denoise_fuzz_targets.h), built here with the project's
// compiler, run on their seeds: each seed is a valid input that reaches past the reader (a
// rejected seed would leave the fuzzer at the parser), and the harnesses end cleanly on it.
#include <gtest/gtest.h>

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "denoise_fuzz_targets.h"
#include "fuzz_replay.h"

namespace glint::fuzz {
namespace {

std::vector<std::vector<std::uint8_t>> seeds(const char* target) {
    std::vector<std::vector<std::uint8_t>> out;
    for (const fs::path& file : seedFiles(target)) out.push_back(readBytes(file));
    return out;
}

std::string text(const std::vector<std::uint8_t>& bytes) {
    return {bytes.begin(), bytes.end()};
}

TEST(DenoiseFuzzSeeds, RendersAndDenoisedFilesReachAuto) {
    // A render with halves and a file apply wrote (keeping that render as its noisy layer):
    // each is read and denoised to a composite of its size, past every check.
    int kept = 0;
    for (const auto& seed : seeds("denoise_input")) {
        runDenoiseInput(seed.data(), seed.size());
        const FrameBuffers file = readExr(workspace() / "input.exr");
        kept += file.has(Layer::Noisy) ? 1 : 0;
        const FrameBuffers frame = denoise::renderOf(file);
        ASSERT_TRUE(frame.has(Layer::HalfColor));
        denoise::BankOptions bank;
        bank.size = 4;
        bank.filters = {"gaussian"};
        const denoise::StreamedAuto result = denoise::autoCompositeStreamed(frame, bank);
        EXPECT_EQ(result.result.composite.width(), frame.width());
        EXPECT_EQ(result.result.estimator, denoise::AutoEstimator::Halves);
    }
    EXPECT_EQ(kept, 1);
}

TEST(DenoiseFuzzRegressions, DenoiseInput) {
    // What fuzz_denoise_input found: each now ends in a clean error or finite output.
    replay("denoise_input", runDenoiseInput);
}

TEST(DenoiseFuzzSeeds, PaintScriptsApplyToTheSmallRender) {
    for (const auto& seed : seeds("paint_script")) {
        const denoise::PaintScript script = denoise::PaintScript::parse(text(seed), "seed.json");
        denoise::Session session(smallRender());
        script.apply(session);
        EXPECT_EQ(session.layerCount(), script.layers().size());
        runPaintScript(seed.data(), seed.size());
    }
}

TEST(DenoiseFuzzSeeds, SessionFilesLoadTheirLayers) {
    for (const auto& seed : seeds("session")) {
        runSessionFile(seed.data(), seed.size());  // writes the workspace's session file
        EXPECT_EQ(denoise::Session::load(workspace() / "fuzz.glint-session.json").layerCount(), 2u);
    }
}

TEST(DenoiseFuzzSeeds, BankIndexesOpenWithEveryMember) {
    // The members' checksums in a seed are those of the build that wrote it; another build
    // (the sanitizers' -O1) may round a filter differently, and the open then recomputes the
    // member in memory. Either way every member of the seed is in the bank.
    for (const auto& seed : seeds("bank_index")) {
        runBankIndex(seed.data(), seed.size());
        const denoise::FilterBank bank = denoise::openBank(smallRender(), workspace() / "bank");
        const auto index = nlohmann::json::parse(text(seed));
        EXPECT_EQ(bank.size(), index.at("members").size());
    }
}

TEST(DenoiseFuzzSeeds, ShardSetsMerge) {
    for (const auto& seed : seeds("shard_merge")) {
        runShardMerge(seed.data(), seed.size());
        if (text(seed).find(kShardSeparator) == std::string::npos) continue;  // one shard: refused
        const FrameBuffers merged = mergeShardFiles(
            {(workspace() / "shard-0.exr").string(), (workspace() / "shard-1.exr").string()});
        EXPECT_EQ(merged.width(), smallRender().width());
    }
}

}  // namespace
}  // namespace glint::fuzz
