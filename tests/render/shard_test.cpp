// Sharded renders (docs/distributed.md): shards of a render merged by glint::mergeShards equal
// the whole render within the stated float tolerance, for 1 to 8 shards and every sampler; the
// merge does not depend on the order of the shards; missing, duplicated and foreign shards are
// refused naming them; a shard of a cancelled render merges by its sample counts; partial merges
// of shard ranges merge again (a tree) within the stated tolerance of the flat merge.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/image/shard.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "test_util.h"

namespace glint::render {
namespace {

/// The Cornell box at `width`×`height`, `emission` on the light (a different scene otherwise).
Scene tinyCornell(int width = 20, int height = 16, int emission = 17) {
    const std::string json = R"({
      "camera": {"position": [278, 273, -800], "lookAt": [278, 273, 0], "fovY": 39.3},
      "film": {"width": )" + std::to_string(width) +
                             R"(, "height": )" + std::to_string(height) + R"(},
      "materials": {"light": {"type": "diffuse", "albedo": [0, 0, 0],
                              "emission": [)" +
                             std::to_string(emission) +
                             R"(, 12, 4]}},
      "shapes": [{"obj": "cornell_box.obj"}],
      "render": {"spp": 8, "maxDepth": 4}
    })";
    return parseScene(json, std::string(GLINT_SOURCE_DIR) + "/scenes/cornell/scene.json");
}

Settings baseSettings(int spp, SamplerKind sampler = SamplerKind::Sobol, std::uint64_t seed = 7) {
    Settings s;
    s.spp = spp;
    s.seed = seed;
    s.sampler = sampler;
    s.maxDepth = 4;
    s.threads = 2;
    s.tileSize = 8;
    return s;
}

std::vector<ShardFrame> renderShards(Renderer& renderer, Settings settings, int count) {
    std::vector<ShardFrame> shards;
    for (int i = 0; i < count; ++i) {
        settings.shard = Shard{i, count};
        shards.push_back({"shard" + std::to_string(i) + ".exr", renderer.render(settings).frame});
    }
    return shards;
}

/// Tallies of a comparison against the stated tolerance.
struct Agreement {
    std::size_t values = 0, identical = 0;
};

/// Expects `merged` to equal `whole` within the tolerance of docs/distributed.md: counts exact;
/// each mean within 4 ulps (4·2^-24) of M, the largest |shard mean| of its pixel and channel;
/// each variance of the mean V within 16·2^-24·V + 8·2^-24·M·√V.
Agreement expectMergeEqualsWhole(const FrameBuffers& merged, const FrameBuffers& whole,
                                 const std::vector<ShardFrame>& shards) {
    constexpr double eps = 0x1p-24;
    Agreement a;
    EXPECT_TRUE(test::sameLayer(merged, whole, Layer::SampleCount));
    for (Layer mean : {Layer::Color, Layer::Albedo, Layer::Normal, Layer::Depth}) {
        const Layer var = *varianceLayer(mean);
        const int channels = layerInfo(mean).channels;
        int failures = 0;
        for (int y = 0; y < whole.height(); ++y)
            for (int x = 0; x < whole.width(); ++x)
                for (int c = 0; c < channels; ++c) {
                    double m = 0.0;
                    for (const ShardFrame& s : shards)
                        m = std::max(m, std::abs(double(s.frame.layer(mean)(x, y, c))));
                    const double mw = whole.layer(mean)(x, y, c), mm = merged.layer(mean)(x, y, c);
                    const double vw = whole.layer(var)(x, y, c), vm = merged.layer(var)(x, y, c);
                    const bool meanOk = std::abs(mm - mw) <= 4.0 * eps * m;
                    const bool varOk =
                        std::abs(vm - vw) <= 16.0 * eps * vw + 8.0 * eps * m * std::sqrt(vw);
                    if ((!meanOk || !varOk) && ++failures <= 3)
                        ADD_FAILURE() << layerInfo(mean).name << " pixel " << x << "," << y
                                      << " channel " << c << ": mean " << mm << " vs " << mw
                                      << ", variance " << vm << " vs " << vw << " (M " << m << ")";
                    a.values += 2;
                    a.identical += (mm == mw) + (vm == vw);
                }
    }
    return a;
}

TEST(Shard, MergeOfOneToEightShardsEqualsTheWholeRender) {
    Renderer renderer(tinyCornell());
    // 11 spp crosses the pass boundaries 1, 2, 4, 8: shards start and end inside passes.
    for (SamplerKind sampler :
         {SamplerKind::Sobol, SamplerKind::Stratified, SamplerKind::Independent}) {
        const Settings settings = baseSettings(11, sampler);
        const FrameBuffers whole = renderer.render(settings).frame;
        Agreement total;
        for (int count = 1; count <= 8; ++count) {
            SCOPED_TRACE(std::string(samplerName(sampler)) + ", " + std::to_string(count) +
                         " shards");
            std::vector<ShardFrame> shards = renderShards(renderer, settings, count);
            for (int i = 0; i < count; ++i) {
                const auto info = shardInfo(shards[std::size_t(i)].frame.metadata(), "shard");
                ASSERT_TRUE(info);
                EXPECT_EQ(info->index, i);
                EXPECT_EQ(info->count, count);
                EXPECT_EQ(info->totalSpp, 11);
                EXPECT_EQ(shards[std::size_t(i)].frame.metadata().spp,
                          info->sampleEnd - info->sampleBegin);
            }
            const FrameBuffers merged = mergeShards(shards);
            EXPECT_EQ(merged.metadata().spp, 11);
            EXPECT_EQ(merged.metadata().seed, 7u);
            const Agreement a = expectMergeEqualsWhole(merged, whole, shards);
            total.values += a.values, total.identical += a.identical;
            if (count == 1) {
                test::expectSameFrames(merged, whole);  // one shard is the whole render
            }
        }
        std::printf("%s: %zu of %zu merged means and variances bit-identical to the whole render\n",
                    samplerName(sampler), total.identical, total.values);
        EXPECT_GT(total.identical, total.values / 2);
    }
}

TEST(Shard, ShardsHoldTheWholeRendersSamplesForAStratifiedSampler) {
    // A stratified pass stratifies over its block of the whole render's samples: a shard of
    // [4, 11) of 11 spp is not a 7-spp render, and the merge only matches when the shard keeps
    // the whole render's passes. Compare shard 1/2 with the same samples rendered as a whole.
    Renderer renderer(tinyCornell());
    Settings settings = baseSettings(11, SamplerKind::Stratified);
    settings.shard = Shard{1, 2};  // samples [5, 11)
    const FrameBuffers shard = renderer.render(settings).frame;
    Settings six = baseSettings(6, SamplerKind::Stratified);
    const FrameBuffers alone = renderer.render(six).frame;
    EXPECT_FALSE(test::sameLayer(shard, alone, Layer::Color));
    EXPECT_EQ(shard.layer(Layer::SampleCount)(3, 3, 0), 6.0f);
}

TEST(Shard, MergeIsTheSameForAnyOrderOfTheShards) {
    Renderer renderer(tinyCornell());
    const std::vector<ShardFrame> shards = renderShards(renderer, baseSettings(9), 4);
    const FrameBuffers reference = mergeShards(shards);
    std::vector<int> order = {0, 1, 2, 3};
    int permutations = 0;
    while (std::next_permutation(order.begin(), order.end())) {
        std::vector<ShardFrame> permuted;
        for (int i : order) permuted.push_back(shards[std::size_t(i)]);
        test::expectSameFrames(mergeShards(permuted), reference);
        ++permutations;
    }
    EXPECT_EQ(permutations, 23);
}

/// The message of the Error mergeShards throws, or "" when it does not throw.
std::string mergeError(const std::vector<ShardFrame>& shards) {
    try {
        mergeShards(shards);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        return e.what();
    }
    return {};
}

TEST(Shard, MergeRefusesMissingDuplicateAndForeignShards) {
    Renderer renderer(tinyCornell());
    const Settings settings = baseSettings(8);
    const std::vector<ShardFrame> shards = renderShards(renderer, settings, 4);

    // Missing: shard 2 of 4, named with the ones given.
    std::vector<ShardFrame> missing = {shards[0], shards[1], shards[3]};
    std::string e = mergeError(missing);
    EXPECT_NE(e.find("missing 2/4"), std::string::npos) << e;
    EXPECT_NE(e.find("shard3.exr (3/4)"), std::string::npos) << e;

    // Duplicated: shard 1 twice under two names.
    std::vector<ShardFrame> twice = shards;
    twice.push_back({"copy.exr", shards[1].frame});
    e = mergeError(twice);
    EXPECT_NE(e.find("1/4 is given twice: shard1.exr and copy.exr"), std::string::npos) << e;

    // Foreign: another seed, another N, another scene, another spp.
    auto foreign = [&](Renderer& r, Settings s, int count, const std::string& expected) {
        s.shard = Shard{1, count};
        std::vector<ShardFrame> set = {
            shards[0], {"other.exr", r.render(s).frame}, shards[2], shards[3]};
        const std::string message = mergeError(set);
        EXPECT_NE(message.find("other.exr"), std::string::npos) << message;
        EXPECT_NE(message.find("foreign"), std::string::npos) << message;
        EXPECT_NE(message.find(expected), std::string::npos) << message;
    };
    foreign(renderer, baseSettings(8, SamplerKind::Sobol, 8), 4, "seed");
    foreign(renderer, settings, 2, "N");
    foreign(renderer, baseSettings(12), 4, "shardTotalSpp");
    foreign(renderer, baseSettings(8, SamplerKind::Stratified), 4, "sampler");
    Renderer brighter(tinyCornell(20, 16, 18));
    foreign(brighter, settings, 4, "sceneHash");

    // Not a shard at all.
    std::vector<ShardFrame> plain = shards;
    plain[2] = {"whole.exr", renderer.render(settings).frame};
    e = mergeError(plain);
    EXPECT_NE(e.find("whole.exr"), std::string::npos) << e;
    EXPECT_NE(e.find("not a shard"), std::string::npos) << e;
}

TEST(Shard, MergeRefusesAShardPixelNoRenderWrites) {
    // Every pixel entering a merge is checked: a count that is negative, fractional, non-finite
    // or above the shard's samples, a half count above its pixel's count, a non-finite mean, a
    // negative or non-finite variance. The error names the file, the pixel and the channel.
    Settings settings = baseSettings(8);
    settings.halfBuffers = true;
    Renderer renderer(tinyCornell());
    const std::vector<ShardFrame> shards = renderShards(renderer, settings, 2);
    ASSERT_NO_THROW(mergeShards(shards));
    const float nan = std::nanf(""), inf = INFINITY;
    struct Case {
        Layer layer;
        int channel;
        float value;
        const char* channelName;
    };
    for (const Case& c : {Case{Layer::SampleCount, 0, -3.0f, "sampleCount.Y"},
                          Case{Layer::SampleCount, 0, 2.5f, "sampleCount.Y"},
                          Case{Layer::SampleCount, 0, nan, "sampleCount.Y"},
                          Case{Layer::SampleCount, 0, 1e30f, "sampleCount.Y"},
                          Case{Layer::SampleCount, 0, 5.0f, "sampleCount.Y"},  // shard holds 4
                          Case{Layer::HalfSampleCount, 0, 5.0f, "halfSampleCount.Y"},
                          Case{Layer::Color, 1, inf, "G"}, Case{Layer::Albedo, 2, nan, "albedo.B"},
                          Case{Layer::Variance, 0, -1e-6f, "variance.R"},
                          Case{Layer::HalfDepthVariance, 0, inf, "halfDepthVariance.Z"}}) {
        std::vector<ShardFrame> bad = shards;
        bad[1].frame.layer(c.layer)(7, 5, c.channel) = c.value;
        try {
            mergeShards(bad);
            ADD_FAILURE() << c.channelName << " = " << c.value << " was merged";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
            EXPECT_EQ(e.file(), "shard1.exr") << e.what();
            EXPECT_EQ(e.where(), std::string("pixel (7, 5) ") + c.channelName) << e.what();
        }
    }
}

/// Shards `first` … `last` of `shards` as a partial merge, named like glint-farm's files.
ShardFrame partial(const std::vector<ShardFrame>& shards, int first, int last) {
    std::vector<ShardFrame> range(shards.begin() + first, shards.begin() + last + 1);
    return {"part-" + std::to_string(first) + "-" + std::to_string(last) + ".exr",
            mergeShards(range, MergeKind::Partial)};
}

TEST(Shard, TreeMergeEqualsTheFlatMergeWithinTolerance) {
    // Tolerance (docs/distributed.md, "Tree merge"): a partial merge stores float32 means and
    // variances, so a tree differs from the flat merge by rounding only: counts exact, each
    // mean within 4·2^-24·M (M the largest |shard mean| of the pixel and channel), each
    // variance of the mean within 16·2^-24·V + 8·2^-24·M·√V (V the flat merge's).
    constexpr double eps = 0x1p-24;
    Renderer renderer(tinyCornell());
    const Settings settings = baseSettings(16);
    const std::vector<ShardFrame> shards = renderShards(renderer, settings, 8);
    const FrameBuffers flat = mergeShards(shards);

    // A partial merge records its range, samples and shard count, and is itself a shard range.
    const ShardFrame p03 = partial(shards, 0, 3);
    const auto info = shardInfo(p03.frame.metadata(), p03.file);
    ASSERT_TRUE(info);
    EXPECT_EQ(p03.frame.metadata().extra.at("shard"), "0-3/8");
    EXPECT_EQ(info->index, 0);
    EXPECT_EQ(info->last(), 3);
    EXPECT_EQ(info->sampleBegin, 0);
    EXPECT_EQ(info->sampleEnd, 8);
    EXPECT_EQ(p03.frame.metadata().spp, 8);
    EXPECT_EQ(p03.frame.metadata().extra.at("mergedShards"), "4");

    const std::vector<std::vector<ShardFrame>> trees = {
        {partial(shards, 0, 3), partial(shards, 4, 7)},
        {partial(shards, 5, 7), shards[4], partial(shards, 0, 2), shards[3]},  // mixed, unordered
        {partial(shards, 0, 7)},
        // Three levels: (0-1, 2-3) → 0-3, then with 4-7.
        {{"part-0-3.exr",
          mergeShards({partial(shards, 0, 1), partial(shards, 2, 3)}, MergeKind::Partial)},
         partial(shards, 4, 7)},
    };
    std::size_t values = 0, identical = 0;
    for (std::size_t t = 0; t < trees.size(); ++t) {
        SCOPED_TRACE("tree " + std::to_string(t));
        const FrameBuffers tree = mergeShards(trees[t]);
        EXPECT_FALSE(shardInfo(tree.metadata(), "tree"));
        EXPECT_EQ(tree.metadata().spp, 16);
        EXPECT_EQ(tree.metadata().extra.at("mergedShards"), "8");
        EXPECT_TRUE(test::sameLayer(tree, flat, Layer::SampleCount));
        for (Layer mean : {Layer::Color, Layer::Albedo, Layer::Normal, Layer::Depth}) {
            const Layer var = *varianceLayer(mean);
            int failures = 0;
            for (int y = 0; y < flat.height(); ++y)
                for (int x = 0; x < flat.width(); ++x)
                    for (int c = 0; c < layerInfo(mean).channels; ++c) {
                        double m = 0.0;
                        for (const ShardFrame& s : shards)
                            m = std::max(m, std::abs(double(s.frame.layer(mean)(x, y, c))));
                        const double mf = flat.layer(mean)(x, y, c), mt = tree.layer(mean)(x, y, c);
                        const double vf = flat.layer(var)(x, y, c), vt = tree.layer(var)(x, y, c);
                        const bool ok =
                            std::abs(mt - mf) <= 4.0 * eps * m &&
                            std::abs(vt - vf) <= 16.0 * eps * vf + 8.0 * eps * m * std::sqrt(vf);
                        if (!ok && ++failures <= 3)
                            ADD_FAILURE() << layerInfo(mean).name << " pixel " << x << "," << y
                                          << " channel " << c << ": mean " << mt << " vs " << mf
                                          << ", variance " << vt << " vs " << vf;
                        values += 2;
                        identical += (mt == mf) + (vt == vf);
                    }
        }
    }
    std::printf("tree merges: %zu of %zu means and variances bit-identical to the flat merge\n",
                identical, values);
    EXPECT_GT(identical, values / 2);
}

/// The message of the Error mergeShards(kind) throws, or "" when it does not throw.
std::string mergeError(const std::vector<ShardFrame>& shards, MergeKind kind) {
    try {
        mergeShards(shards, kind);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        return e.file() + ": " + e.what();
    }
    return {};
}

TEST(Shard, TreeMergeRefusesGapsAndOverlapsNamingTheFiles) {
    Renderer renderer(tinyCornell());
    const std::vector<ShardFrame> shards = renderShards(renderer, baseSettings(8), 8);
    const ShardFrame p03 = partial(shards, 0, 3), p37 = partial(shards, 3, 7),
                     p47 = partial(shards, 4, 7), p02 = partial(shards, 0, 2);

    std::string e = mergeError({p03, p37}, MergeKind::Whole);  // overlap at shard 3
    EXPECT_NE(e.find("part-3-7.exr"), std::string::npos) << e;
    EXPECT_NE(e.find("part-0-3.exr"), std::string::npos) << e;
    EXPECT_NE(e.find("overlap"), std::string::npos) << e;
    e = mergeError({p47, shards[5], p03}, MergeKind::Whole);  // a shard inside a range
    EXPECT_NE(e.find("shard5.exr"), std::string::npos) << e;
    EXPECT_NE(e.find("part-4-7.exr"), std::string::npos) << e;
    e = mergeError({p02, p47}, MergeKind::Whole);  // gap: shard 3
    EXPECT_NE(e.find("missing 3/8; given part-0-2.exr (0-2/8), part-4-7.exr (4-7/8)"),
              std::string::npos)
        << e;
    e = mergeError({p03}, MergeKind::Whole);  // the tail missing
    EXPECT_NE(e.find("missing 4-7/8"), std::string::npos) << e;
    e = mergeError({shards[0], shards[2]}, MergeKind::Partial);  // not contiguous
    EXPECT_NE(e.find("contiguous range: missing 1/8"), std::string::npos) << e;
    e = mergeError({p02, shards[2]}, MergeKind::Partial);
    EXPECT_NE(e.find("overlap"), std::string::npos) << e;
    EXPECT_NE(e.find("shard2.exr"), std::string::npos) << e;

    // A partial merge of another render is foreign like a shard of it.
    Settings other = baseSettings(8, SamplerKind::Sobol, 8);
    const ShardFrame q47 = partial(renderShards(renderer, other, 8), 4, 7);
    e = mergeError({p03, q47}, MergeKind::Whole);
    EXPECT_NE(e.find("foreign"), std::string::npos) << e;
    EXPECT_NE(e.find("seed"), std::string::npos) << e;
    EXPECT_EQ(mergeError({p03, shards[4], partial(shards, 5, 7)}, MergeKind::Whole), "");
}

TEST(Shard, RangeAttributesRoundTripAndMalformedOnesAreRefused) {
    FrameMetadata md;
    ShardInfo info{2, 16, 64, 0, 0, 0xabcdefull};
    info.lastIndex = 9;
    std::tie(info.sampleBegin, std::ignore) = shardSampleRange(64, 2, 16);
    info.sampleEnd = shardSampleRange(64, 9, 16).second;
    setShardInfo(md, info);
    EXPECT_EQ(md.extra.at("shard"), "2-9/16");
    EXPECT_EQ(md.extra.at("shardSamples"), "8 40");
    const auto back = shardInfo(md, "x.exr");
    ASSERT_TRUE(back);
    EXPECT_EQ(back->index, 2);
    EXPECT_EQ(back->last(), 9);
    EXPECT_EQ(back->count, 16);
    for (const std::string bad : {"9-2/16", "2-16/16", "-2/16", "2-/16", "2-9", "a-9/16"}) {
        FrameMetadata m = md;
        m.extra["shard"] = bad;
        EXPECT_THROW(shardInfo(m, "x.exr"), Error) << bad;
    }
    FrameMetadata wrongSamples = md;
    wrongSamples.extra["shardSamples"] = "8 12";  // those of shards 2-2, not 2-9
    EXPECT_THROW(shardInfo(wrongSamples, "x.exr"), Error);
}

TEST(Shard, SameSceneHashesTheSameWherever) {
    Renderer a(tinyCornell()), b(tinyCornell()), c(tinyCornell(20, 16, 18));
    Settings s = baseSettings(2);
    s.shard = Shard{0, 2};
    const auto hash = [&](Renderer& r) {
        return shardInfo(r.render(s).frame.metadata(), "x")->sceneHash;
    };
    EXPECT_EQ(hash(a), hash(b));
    EXPECT_NE(hash(a), hash(c));
}

TEST(Shard, CancelledShardMergesByItsCounts) {
    Renderer renderer(tinyCornell());
    const Settings settings = baseSettings(8);
    std::vector<ShardFrame> shards = renderShards(renderer, settings, 2);  // [0,4) and [4,8)

    // Cancel shard 0 after 15 of its tiles (6 tiles per pass, passes [0,1), [1,2), [2,4)): a
    // pixel then holds 2 or 4 of its first samples, and its count says how many.
    Settings first = settings;
    first.shard = Shard{0, 2};
    int tiles = 0;
    Callbacks callbacks;
    callbacks.tileDone = [&](const Rect&) { ++tiles; };
    callbacks.cancel = [&] { return tiles >= 15; };
    RenderResult cancelled = renderer.render(first, callbacks);
    ASSERT_TRUE(cancelled.stats.cancelled);
    shards[0] = {"cancelled.exr", cancelled.frame};
    const FrameBuffers merged = mergeShards(shards);
    EXPECT_EQ(merged.metadata().extra.at("cancelled"), "true");

    // What the cancelled shard's pixels must hold: with Sobol, samples [0, c) are those of a
    // whole c-spp render.
    std::vector<FrameBuffers> prefix(5);
    for (int c : {2, 4}) prefix[std::size_t(c)] = renderer.render(baseSettings(c)).frame;
    const FrameBuffers& rest = shards[1].frame;
    std::vector<int> seen(5, 0);
    for (int y = 0; y < merged.height(); ++y)
        for (int x = 0; x < merged.width(); ++x) {
            const int c = int(cancelled.frame.layer(Layer::SampleCount)(x, y, 0));
            ASSERT_TRUE(c == 2 || c == 4) << c;
            ++seen[std::size_t(c)];
            EXPECT_EQ(merged.layer(Layer::SampleCount)(x, y, 0), float(c + 4));
            for (int ch = 0; ch < 3; ++ch) {
                // The shard's pixel is the c-spp render's (same samples, same Welford order).
                EXPECT_EQ(cancelled.frame.color()(x, y, ch),
                          prefix[std::size_t(c)].color()(x, y, ch));
                // The merge weighs it by c against the 4 samples of the other shard.
                const double expected = (c * double(prefix[std::size_t(c)].color()(x, y, ch)) +
                                         4.0 * double(rest.color()(x, y, ch))) /
                                        double(c + 4);
                EXPECT_NEAR(merged.color()(x, y, ch), expected, 4e-7 * std::abs(expected) + 1e-30);
            }
        }
    EXPECT_GT(seen[4], 0);  // tiles that finished the cancelled pass
    EXPECT_GT(seen[2], 0);  // and tiles that did not
}

TEST(Shard, SettingsRefuseShardsThatCannotBeMerged) {
    Settings s = baseSettings(4);
    auto refused = [&](Shard shard) {
        s.shard = shard;
        try {
            validate(s);
        } catch (const Error& e) {
            return e.where() == "shard";
        }
        return false;
    };
    EXPECT_TRUE(refused({0, 5}));  // more shards than samples
    EXPECT_TRUE(refused({4, 4}));
    EXPECT_TRUE(refused({-1, 4}));
    EXPECT_FALSE(refused({3, 4}));
    s.timeLimit = 1.0;
    EXPECT_TRUE(refused({0, 2}));
    s.timeLimit = 0.0;
    s.integrator = Integrator::Mlt;
    EXPECT_TRUE(refused({0, 2}));
}

TEST(Shard, SampleRangesPartitionTheSamples) {
    for (int spp : {1, 7, 64, 4096})
        for (int count = 1; count <= std::min(spp, 70); ++count) {
            int next = 0;
            for (int i = 0; i < count; ++i) {
                const auto [begin, end] = shardSampleRange(spp, i, count);
                EXPECT_EQ(begin, next);
                EXPECT_LT(begin, end);
                next = end;
            }
            EXPECT_EQ(next, spp);
        }
}

}  // namespace
}  // namespace glint::render
