// Filters that report progress, stop when told to, and share the threads (WorkContext,
// FilterOptions); choice parameters and parameter-dependent feature layers.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

class EveryFilter : public ::testing::TestWithParam<const Filter*> {};

// Progress goes up, ends at exactly 1, and the result equals a run without a callback.
TEST_P(EveryFilter, ReportsMonotoneProgressEndingAtOne) {
    const Filter& f = *GetParam();
    const FrameBuffers frame = testing::syntheticFrame(96, 80);
    std::vector<double> seen;
    FilterOptions options;
    options.progress = [&](double fraction) {
        seen.push_back(fraction);
        return true;
    };
    const Image out = applyFilter(f, frame, {}, options);
    ASSERT_FALSE(seen.empty()) << f.name();
    for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_GE(seen[i], seen[i - 1]) << f.name();
    EXPECT_EQ(seen.back(), 1.0) << f.name();
    for (std::size_t i = 0; i + 1 < seen.size(); ++i) EXPECT_LT(seen[i], 1.0) << f.name();
    EXPECT_EQ(testing::maxAbsDiff(out, applyFilter(f, frame, {})), 0.0) << f.name();
}

// Returning false from the first call stops the filter: Error(Cancelled), no further calls.
TEST_P(EveryFilter, StopsWhenTheCallbackSaysStop) {
    const Filter& f = *GetParam();
    const FrameBuffers frame = testing::syntheticFrame(256, 192);
    int calls = 0;
    FilterOptions options;
    options.progress = [&](double) {
        ++calls;
        return false;
    };
    try {
        applyFilter(f, frame, {}, options);
        ADD_FAILURE() << f.name() << " was not cancelled";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Cancelled) << f.name() << ": " << e.what();
    }
    EXPECT_EQ(calls, 1) << f.name();
}

// The same result on a private pool of 1 or 2 threads as in the caller's pool.
TEST_P(EveryFilter, ThreadCountDoesNotChangeTheResult) {
    const Filter& f = *GetParam();
    const FrameBuffers frame = testing::syntheticFrame(70, 50);
    const Image shared = applyFilter(f, frame, {});
    for (int threads : {1, 2}) {
        FilterOptions options;
        options.threads = threads;
        EXPECT_EQ(testing::maxAbsDiff(applyFilter(f, frame, {}, options), shared), 0.0)
            << f.name() << " threads " << threads;
    }
}

INSTANTIATE_TEST_SUITE_P(All, EveryFilter, ::testing::ValuesIn(testing::runnableFilters()),
                         [](const ::testing::TestParamInfo<const Filter*>& info) {
                             std::string n(info.param->name());
                             for (char& c : n)
                                 if (c == '-') c = '_';
                             return n;
                         });

// A filter that does one unit of work per row and counts the rows it filtered.
class RowCounter final : public Filter {
  public:
    mutable std::atomic<int> rows{0};
    std::string_view name() const override { return "row-counter"; }
    std::string_view description() const override { return "counts rows"; }
    const std::vector<ParamSpec>& params() const override { return m_params; }
    int margin(const ParamValues&) const override { return 0; }
    Image apply(const FrameBuffers& frame, const ParamValues&, const Rect& roi,
                WorkContext& work) const override {
        Image out = frame.color().crop(roi);
        work.parallelFor(roi.y0, roi.y1, [&](int) { ++rows; });
        return out;
    }

  private:
    std::vector<ParamSpec> m_params;
};

TEST(FilterCancel, StopsWithinOneRowPerThread) {
    RowCounter counter;
    const FrameBuffers frame(8, 4096);
    int rowsAtCancel = -1;
    FilterOptions options;
    options.threads = 2;
    options.progress = [&](double) {
        if (counter.rows.load() < 100) return true;
        rowsAtCancel = counter.rows.load();
        return false;
    };
    EXPECT_THROW(applyFilter(counter, frame, {}, options), Error);
    ASSERT_GE(rowsAtCancel, 100);
    // Each of the 2 threads finishes at most the row it is on.
    EXPECT_LE(counter.rows.load(), rowsAtCancel + 2);
    EXPECT_LT(counter.rows.load(), 4096);
}

TEST(FilterOptionsTest, AbsurdThreadCountsAreRefused) {
    const FrameBuffers frame = testing::syntheticFrame(8, 8);
    FilterOptions options;
    options.threads = -1;
    EXPECT_THROW(applyFilter(findFilter("gaussian"), frame, {}, options), Error);
}

TEST(ChoiceParam, ParsesNamesAndIndicesAndFormatsNames) {
    const ParamSpec* guide = findParam(findFilter("guided").params(), "guide");
    ASSERT_NE(guide, nullptr);
    ASSERT_TRUE(guide->isChoice());
    EXPECT_EQ(guide->choices.size(), 4u);
    EXPECT_EQ(guide->min, 0.0);
    EXPECT_EQ(guide->max, 3.0);
    EXPECT_EQ(parseParamValue(*guide, "albedo"), 1.0);
    EXPECT_EQ(parseParamValue(*guide, "2"), 2.0);
    EXPECT_EQ(formatParamValue(*guide, 3.0), "depth");
    try {
        parseParamValue(*guide, "albedos");
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
    }
    EXPECT_THROW(resolveParams(findFilter("guided"), {{"guide", 1.5}}), Error);
    const ParamSpec* pattern = findParam(findFilter("bilateral-mc").params(), "pattern");
    ASSERT_NE(pattern, nullptr);
    EXPECT_TRUE(pattern->isChoice());
    EXPECT_EQ(parseParamValue(*pattern, "poisson"), 0.0);
}

TEST(RequiredLayers, DependOnTheParameters) {
    const Filter& guided = findFilter("guided");
    EXPECT_TRUE(guided.requiredLayers(resolveParams(guided, {{"guide", 0}})).empty());
    EXPECT_EQ(guided.requiredLayers(resolveParams(guided, {{"guide", 3}})),
              std::vector<Layer>{Layer::Depth});
    FrameBuffers bare(16, 16);
    bare.color() = testing::syntheticFrame(16, 16).color();
    EXPECT_NO_THROW(applyFilter(guided, bare, {{"guide", 0}}));
    try {
        applyFilter(guided, bare, {{"guide", 2}});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("normal"), std::string::npos) << e.what();
    }
}

TEST(PrefilterParams, AreParamSpecsWithDefaults) {
    const std::vector<ParamSpec>& specs = prefilterParams();
    ASSERT_EQ(specs.size(), 3u);
    const ParamValues resolved = resolveParams(specs, {}, "feature prefilter");
    EXPECT_EQ(resolved.at("radius"), 3.0);
    EXPECT_EQ(resolved.at("sigmaSpatial"), 1.5);
    try {
        prefilterFeatures(testing::syntheticFrame(8, 8), {{"sigma", 1.0}});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("varianceScale"), std::string::npos) << e.what();
    }
    // The prefilter stops too.
    EXPECT_THROW(
        prefilterFeatures(testing::syntheticFrame(64, 64), {}, [](double) { return false; }),
        Error);
}

}  // namespace
}  // namespace glint::denoise
