// The journal fuzz harness (tests/fuzz/journal_fuzz_target.h), built here with the project's
// compiler and run on its seeds: each seed is a journal the studio could have left that restores
// whole (a refused seed would leave the fuzzer at the first line), and the harness ends cleanly
// on it; the fixture's side files are what the seeds name.
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

#include "fuzz_replay.h"
#include "journal_fuzz_target.h"

namespace glint::fuzz {
namespace {

struct Seed {
    std::string name;
    std::vector<std::uint8_t> bytes;
    std::size_t lines = 0;
};

std::vector<Seed> seeds() {
    std::vector<Seed> out;
    for (const fs::path& file : seedFiles("journal")) {
        Seed seed{file.filename().string(), readBytes(file)};
        for (std::uint8_t c : seed.bytes) seed.lines += c == '\n' ? 1 : 0;
        out.push_back(std::move(seed));
    }
    EXPECT_GE(out.size(), 4u) << "journal seeds";
    return out;
}

TEST(JournalFuzzSeeds, EverySeedRestoresWholeWithASessionWhereItStartsOne) {
    for (const Seed& seed : seeds()) {
        SCOPED_TRACE(seed.name);
        std::string refusal;
        const auto restored = runJournal(seed.bytes.data(), seed.bytes.size(), &refusal);
        ASSERT_TRUE(restored) << refusal;
        EXPECT_TRUE(restored->complete);
        EXPECT_EQ(std::size_t(restored->edits), seed.lines);
        // Every seed but the one that ends by clearing its second session holds one.
        const bool cleared =
            std::string(seed.bytes.begin(), seed.bytes.end()).ends_with("{\"op\":\"clear\"}\n");
        EXPECT_EQ(bool(restored->session), !cleared);
    }
}

TEST(JournalFuzzSeeds, TheSeedsReachEveryKindOfEdit) {
    // The operations the studio journals (model/journal_codec.h and recovery.cpp): a seed set
    // that lacks one leaves the fuzzer to find its spelling.
    std::string all;
    for (const Seed& seed : seeds()) all.append(seed.bytes.begin(), seed.bytes.end());
    for (const char* op :
         {"open",     "pixels",    "settings",    "look",        "reference", "start",   "input",
          "addLayer", "addLayers", "removeLayer", "renameLayer", "weights",   "fill",    "stroke",
          "apply",    "clear",     "undo",        "redo",        "region",    "setLook", "view"})
        EXPECT_NE(all.find("\"op\":\"" + std::string(op) + "\""), std::string::npos) << op;
}

TEST(JournalFuzzSeeds, TheEditsSeedRestoresItsLayersLookSettingsRegionAndView) {
    for (const Seed& seed : seeds()) {
        if (seed.name != "edits.jsonl") continue;
        const auto r = runJournal(seed.bytes.data(), seed.bytes.size());
        ASSERT_TRUE(r && r->session);
        // gaussian, bilateral added; undo, undo, redo: the rename undone; the first removed.
        ASSERT_EQ(r->session->layerCount(), 1u);
        EXPECT_EQ(r->session->layer(0).filter, "bilateral");
        // The look edit, then a session file's look (no undo step), and the lasso.
        ASSERT_EQ(r->look.size(), 2u);
        EXPECT_EQ(r->look[0].item, "white");
        EXPECT_EQ(r->look[1].item, "red");
        EXPECT_EQ(r->look[1].value, (std::array<double, 3>{0.5, 0.1, 0.1}));
        EXPECT_EQ(r->lasso, (std::vector<double>{2, 2, 10, 2, 6, 9}));
        ASSERT_TRUE(r->view);  // the exposure, Keep Refining and the stage
        EXPECT_EQ(r->view->exposure, 1.5);
        EXPECT_TRUE(r->view->keepRefining);
        EXPECT_EQ(r->view->stage, std::optional<int>(3));
        ASSERT_TRUE(r->settings);
        EXPECT_EQ(r->settings->spp, 64);
        EXPECT_TRUE(r->referenceSet);
        return;
    }
    FAIL() << "no edits.jsonl";
}

}  // namespace
}  // namespace glint::fuzz
