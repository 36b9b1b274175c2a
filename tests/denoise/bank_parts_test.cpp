// A bank built in parts (BankOptions::members, glint-denoise bank --members a:b), as machines
// sharing one folder build it: the folder ends identical to one machine's build, index.json
// appears only when the last part is in, other banks' parts are passed over, bad ranges refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <unistd.h>

#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

namespace fs = std::filesystem;
using testing::maxAbsDiff;
using testing::syntheticFrame;

fs::path freshFolder(const std::string& name) {
    const fs::path p =
        fs::temp_directory_path() / ("glint_bank_parts_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

std::string bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// File names of a folder.
std::set<std::string> listing(const fs::path& dir) {
    std::set<std::string> names;
    for (const fs::directory_entry& e : fs::directory_iterator(dir))
        names.insert(e.path().filename().string());
    return names;
}

BankOptions smallBank(const fs::path& dir) {
    BankOptions o;
    o.size = 7;
    o.seed = 3;
    o.filters = {"gaussian", "bilateral", "cross-bilateral"};
    o.cacheDir = dir;
    return o;
}

TEST(BankParts, PartsInAnyOrderGiveTheFolderOfOneBuild) {
    const FrameBuffers frame = syntheticFrame(24, 20);
    const fs::path whole = freshFolder("whole"), parts = freshFolder("parts");
    const FilterBank one = buildBank(frame, smallBank(whole));
    const std::size_t n = one.size();
    ASSERT_GE(n, 9u);

    // Three parts, the last first; the range of the last runs past the end (clamped).
    const std::pair<int, int> ranges[] = {{6, 100}, {0, 3}, {3, 6}};
    for (std::size_t k = 0; k < 3; ++k) {
        BankOptions o = smallBank(parts);
        o.members = ranges[k];
        const FilterBank part = buildBank(frame, o);
        EXPECT_EQ(part.firstMember(), std::size_t(ranges[k].first));
        EXPECT_EQ(part.bankMembers(), n);
        EXPECT_EQ(part.size(), std::min<std::size_t>(n, std::size_t(ranges[k].second)) -
                                   std::size_t(ranges[k].first));
        for (std::size_t i = 0; i < part.size(); ++i)
            EXPECT_EQ(maxAbsDiff(part.result(i), one.result(part.firstMember() + i)), 0.0);
        const bool last = k == 2;
        EXPECT_EQ(part.indexWritten(), last);
        EXPECT_EQ(fs::exists(parts / "index.json"), last);
    }
    // The same files and no partial index left: index.json byte for byte (it names every
    // member's key and pixel checksum), the members' pixels (their EXRs differ in capDate).
    EXPECT_EQ(listing(parts), listing(whole));
    EXPECT_EQ(bytes(parts / "index.json"), bytes(whole / "index.json"));
    for (const std::string& name : listing(whole)) {
        if (name.rfind("m-", 0) != 0) continue;
        EXPECT_EQ(maxAbsDiff(readExr(parts / name).color(), readExr(whole / name).color()), 0.0)
            << name;
    }

    // The folder opens as the whole bank, every member from the cache.
    const FilterBank reopened = openBank(frame, parts);
    EXPECT_EQ(reopened.size(), n);
    EXPECT_EQ(reopened.cacheHits(), n);
    fs::remove_all(whole);
    fs::remove_all(parts);
}

TEST(BankParts, PartsOfAnotherBankDoNotComplete) {
    const FrameBuffers frame = syntheticFrame(24, 20);
    const fs::path dir = freshFolder("other");
    BankOptions a = smallBank(dir);
    a.members = std::pair{0, 4};
    buildBank(frame, a);
    // The rest of the bank with another seed: its own first part is missing.
    BankOptions b = smallBank(dir);
    b.seed = 4;
    b.members = std::pair{4, 100};
    EXPECT_FALSE(buildBank(frame, b).indexWritten());
    EXPECT_FALSE(fs::exists(dir / "index.json"));
    // The right rest completes the first bank.
    a.members = std::pair{4, 100};
    EXPECT_TRUE(buildBank(frame, a).indexWritten());
    EXPECT_EQ(readBankOptions(dir).seed, 3u);
    fs::remove_all(dir);
}

TEST(BankParts, BadRangesAreRefused) {
    const FrameBuffers frame = syntheticFrame(8, 8);
    const fs::path dir = freshFolder("bad");
    for (const auto& range : {std::pair{-1, 2}, std::pair{5, 2}}) {
        BankOptions o = smallBank(dir);
        o.members = range;
        try {
            buildBank(frame, o);
            ADD_FAILURE() << "range " << range.first << ":" << range.second << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "--members");
        }
    }
    BankOptions noFolder = smallBank({});
    noFolder.members = std::pair{0, 2};
    EXPECT_THROW(buildBank(frame, noFolder), Error);
    EXPECT_TRUE(listing(dir).empty());
    fs::remove_all(dir);
}

}  // namespace
}  // namespace glint::denoise
