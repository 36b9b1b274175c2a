// Properties every registered filter must have, run for each filter of allFilters() through the
// public API only: constant images stay constant, finite in → finite out, NaN/Inf do not spread
// beyond the filter's margin, a region of interest equals the same region of the full output,
// and parameter/size/radiance extremes give no NaN and no crash. Also the checks of
// resolveParams/applyFilter.
//
// Non-finite policy (denoise/src/filters/filter_util.h, docs/denoise.md): a pixel with a NaN/Inf
// colour channel is missing — zero weight as a neighbour; its own output is built from its
// finite neighbours (0 if none) — so the output is finite everywhere and equals the clean-input
// output at every pixel farther than margin() from the bad pixels. A filter of another kind
// says so through Filter::traits() (unet: a prediction that reads NaN as 0, as OIDN does), and
// the tests hold it to what its kind promises; no test asks for a filter's name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "synthetic_frames.h"

namespace glint::denoise {
namespace {

using testing::constantFrame;
using testing::syntheticFrame;

// Filter names for the parameterised suite; a registry failure becomes a failing test.
std::vector<std::string> filterNames() {
    try {
        std::vector<std::string> names;
        for (const Filter* f : testing::runnableFilters()) names.emplace_back(f->name());
        return names;
    } catch (const std::exception& e) {
        return {std::string("registry-failed: ") + e.what()};
    }
}

bool allFinite(const Image& image) {
    return image.countNonFinite() == 0;
}

// |a - b| <= tol * (1 + |b|) everywhere.
::testing::AssertionResult closeRelative(const Image& a, const Image& b, double tol) {
    if (!a.sameShape(b)) return ::testing::AssertionFailure() << "shapes differ";
    for (int y = 0; y < a.height(); ++y)
        for (int x = 0; x < a.width(); ++x)
            for (int c = 0; c < a.channels(); ++c) {
                const double va = a(x, y, c), vb = b(x, y, c);
                if (!(std::fabs(va - vb) <= tol * (1.0 + std::fabs(vb))))
                    return ::testing::AssertionFailure()
                           << "pixel (" << x << "," << y << ") channel " << c << ": " << va
                           << " vs " << vb;
            }
    return ::testing::AssertionSuccess();
}

class FilterProperties : public ::testing::TestWithParam<std::string> {
  protected:
    const Filter& filter() const { return findFilter(GetParam()); }
};

// What a constant image gives, by the kind of output the filter declares (FilterTraits): an
// average keeps every pixel to 1e-5 at any radiance. A prediction (unet) is held at the radiance
// it was trained for: the mean within kPredictionMean and every pixel within kPredictionPixel of
// the constant, relative (measured for unet: 0.021 and 0.252, the border moved most by the zero
// padding of its convolutions); at 1e-30 and 1e30 only finite and non-negative (unet's
// autoexposure leaves a frame darker than its threshold unexposed, so a radiance of 1e-30 comes
// out as the network's small offset, not as a scaled constant).
constexpr double kPredictionMean = 0.05, kPredictionPixel = 0.3;

TEST_P(FilterProperties, ConstantImageStaysConstant) {
    const Filter& f = filter();
    const bool average = f.traits().output == FilterTraits::Output::Average;
    for (float scale : {1.0f, 1e-30f, 1e30f}) {
        SCOPED_TRACE("radiance scale " + std::to_string(scale));
        const FrameBuffers frame =
            constantFrame(19, 13, 0.25f * scale, 0.5f * scale, 0.75f * scale);
        const Image out = applyFilter(f, frame, {});
        ASSERT_EQ(out.width(), 19);
        ASSERT_EQ(out.height(), 13);
        double sum = 0.0, worst = 0.0;
        for (int y = 0; y < out.height(); ++y)
            for (int x = 0; x < out.width(); ++x)
                for (int c = 0; c < 3; ++c) {
                    const double expected = 0.25 * (c + 1), got = out(x, y, c) / scale;
                    if (average) {
                        ASSERT_NEAR(got, expected, 1e-5) << "pixel (" << x << "," << y << ")";
                    } else {
                        ASSERT_TRUE(std::isfinite(out(x, y, c)) && out(x, y, c) >= 0.0f)
                            << "pixel (" << x << "," << y << "): " << out(x, y, c);
                    }
                    sum += std::fabs(got - expected) / expected;
                    worst = std::max(worst, std::fabs(got - expected) / expected);
                }
        if (average || scale != 1.0f) continue;
        EXPECT_LE(sum / (19 * 13 * 3), kPredictionMean);
        EXPECT_LE(worst, kPredictionPixel);
    }
}

TEST_P(FilterProperties, FiniteInputGivesFiniteOutput) {
    const Filter& f = filter();
    const FrameBuffers frame = syntheticFrame(23, 17, 0.1f);
    const Image out = applyFilter(f, frame, {});
    EXPECT_TRUE(allFinite(out));
    // A smoothing filter keeps the output in a sane band around the data (range 0..1 + noise).
    for (float v : out.data()) {
        EXPECT_GT(v, -1.0f);
        EXPECT_LT(v, 2.0f);
    }
}

// Glint's policy (FilterTraits::Missing::Neighbours): a NaN and an Inf change nothing farther
// than the margin.
void expectMissingPixelsStayLocal(const Filter& f) {
    // The frame is sized from the margin so that a band of pixels lies beyond it.
    const int margin = f.margin(resolveParams(f, {}));
    const int w = 2 * margin + 14, h = 2 * margin + 12;
    const FrameBuffers clean = syntheticFrame(w, h, 0.05f);
    FrameBuffers dirty = clean;
    const int nx = 1, ny = 2, ix = w - 2, iy = h - 1;
    dirty.color()(nx, ny, 1) = std::numeric_limits<float>::quiet_NaN();
    dirty.color()(ix, iy, 0) = std::numeric_limits<float>::infinity();
    const Image a = applyFilter(f, clean, {});
    const Image b = applyFilter(f, dirty, {});
    EXPECT_TRUE(allFinite(b)) << "non-finite pixels must count as missing, not propagate";
    int compared = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const bool far = std::max(std::abs(x - nx), std::abs(y - ny)) > margin &&
                             std::max(std::abs(x - ix), std::abs(y - iy)) > margin;
            if (!far) continue;
            ++compared;
            for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(b(x, y, c), a(x, y, c), 1e-5 * (1.0 + std::fabs(a(x, y, c))))
                    << "pixel (" << x << "," << y << ") beyond margin " << margin;
        }
    EXPECT_GT(compared, 0) << "margin " << margin << " covers the whole test frame";
}

// OIDN's reading (FilterTraits::Missing::ReadAsZero): a NaN and a -Inf give exactly the output
// of the frame with 0 there, and a +Inf gives a finite output.
void expectMissingPixelsReadAsZero(const Filter& f) {
    const FrameBuffers clean = syntheticFrame(40, 36, 0.05f);
    FrameBuffers zeroed = clean, dirty = clean;
    for (const auto& [x, y, c] : {std::tuple{1, 2, 1}, std::tuple{30, 20, 0}}) {
        zeroed.color()(x, y, c) = 0.0f;
        dirty.color()(x, y, c) = std::numeric_limits<float>::quiet_NaN();
    }
    dirty.color()(30, 20, 0) = -std::numeric_limits<float>::infinity();
    const Image expected = applyFilter(f, zeroed, {});
    const Image b = applyFilter(f, dirty, {});
    ASSERT_TRUE(allFinite(b));
    EXPECT_TRUE(closeRelative(b, expected, 1e-6));
    FrameBuffers bright = clean;
    bright.color()(5, 6, 2) = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(allFinite(applyFilter(f, bright, {})));
}

TEST_P(FilterProperties, NonFiniteInputIsReadAsTheFilterDeclares) {
    const Filter& f = filter();
    switch (f.traits().missing) {
        case FilterTraits::Missing::Neighbours:
            expectMissingPixelsStayLocal(f);
            break;
        case FilterTraits::Missing::ReadAsZero:
            expectMissingPixelsReadAsZero(f);
            break;
    }
}

TEST_P(FilterProperties, RoiEqualsSameRegionOfFullOutput) {
    const Filter& f = filter();
    const FrameBuffers frame = syntheticFrame(37, 29, 0.08f);
    const Image full = applyFilter(f, frame, {});
    for (const Rect roi : {Rect{5, 17, 3, 14}, Rect{0, 37, 20, 29}, Rect{36, 37, 0, 1}}) {
        SCOPED_TRACE("roi x " + std::to_string(roi.x0) + ".." + std::to_string(roi.x1) + " y " +
                     std::to_string(roi.y0) + ".." + std::to_string(roi.y1));
        const Image part = applyFilter(f, frame, {}, testing::inRegion(roi));
        EXPECT_TRUE(closeRelative(part, full.crop(roi), 1e-5));
    }
}

TEST_P(FilterProperties, ParameterExtremesGiveNoNaN) {
    const Filter& f = filter();
    const FrameBuffers frame = syntheticFrame(12, 9, 0.1f);
    std::vector<ParamValues> settings;
    ParamValues allMin, allMax;
    for (const ParamSpec& spec : f.params()) {
        settings.push_back({{spec.name, spec.min}});
        settings.push_back({{spec.name, spec.max}});
        allMin[spec.name] = spec.min;
        allMax[spec.name] = spec.max;
    }
    settings.push_back(allMin);
    settings.push_back(allMax);
    for (const ParamValues& p : settings) {
        std::string label;
        for (const auto& [k, v] : p) label += k + "=" + std::to_string(v) + " ";
        SCOPED_TRACE(label);
        const Image out = applyFilter(f, frame, p);
        EXPECT_EQ(out.width(), 12);
        EXPECT_TRUE(allFinite(out));
    }
}

TEST_P(FilterProperties, TinyImagesAndExtremeRadianceGiveNoNaN) {
    const Filter& f = filter();
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {1, 7}, {7, 1}, {2, 3}}) {
        for (float scale : {1e-30f, 1.0f, 1e30f}) {
            SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h) + " scale " +
                         std::to_string(scale));
            FrameBuffers frame = syntheticFrame(w, h, 0.1f);
            for (float& v : frame.color().data()) v *= scale;
            const Image out = applyFilter(f, frame, {});
            ASSERT_EQ(out.width(), w);
            ASSERT_EQ(out.height(), h);
            EXPECT_TRUE(allFinite(out));
        }
    }
}

INSTANTIATE_TEST_SUITE_P(AllFilters, FilterProperties, ::testing::ValuesIn(filterNames()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string n;
                             for (char ch : info.param)
                                 n += std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
                             return n;
                         });

// ---- resolveParams / applyFilter / registry -----------------------------------------------

TEST(FilterApi, RegistryHasUniqueNamesDescriptionsAndSaneSpecs) {
    std::vector<std::string> seen;
    for (const Filter* f : allFilters()) {
        EXPECT_FALSE(f->description().empty()) << f->name();
        EXPECT_EQ(std::count(seen.begin(), seen.end(), std::string(f->name())), 0);
        seen.emplace_back(f->name());
        for (const ParamSpec& s : f->params()) {
            EXPECT_LE(s.min, s.defaultValue) << f->name() << "." << s.name;
            EXPECT_LE(s.defaultValue, s.max) << f->name() << "." << s.name;
            if (s.scale == ParamScale::Log) {
                EXPECT_GT(s.min, 0.0) << f->name() << "." << s.name;
            }
        }
    }
    EXPECT_NO_THROW(findFilter("gaussian"));
    EXPECT_NO_THROW(findFilter("bilateral"));
    EXPECT_NO_THROW(findFilter("bilateral-mc"));
}

TEST(FilterApi, UnknownFilterNameListsValidNames) {
    try {
        findFilter("gausian");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("bilateral-mc"), std::string::npos);
    }
}

TEST(FilterApi, ResolveParamsFillsDefaultsAndRejectsBadValues) {
    const Filter& f = findFilter("bilateral");
    const ParamValues r = resolveParams(f, {{"sigmaS", 2.0}});
    EXPECT_EQ(r.at("sigmaS"), 2.0);
    EXPECT_EQ(r.size(), f.params().size());
    auto expectInvalid = [&](const ParamValues& p, const std::string& mention) {
        try {
            resolveParams(f, p);
            ADD_FAILURE() << "expected an error mentioning " << mention;
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
        }
    };
    expectInvalid({{"sigma", 1.0}}, "sigmaR");  // unknown name: message lists valid ones
    expectInvalid({{"sigmaS", -1.0}}, "range");
    expectInvalid({{"sigmaS", 1e7}}, "range");
    expectInvalid({{"sigmaR", std::nan("")}}, "sigmaR");
    expectInvalid({{"radius", 2.5}}, "integer");
}

TEST(FilterApi, ApplyFilterChecksRoiAndRequiredLayers) {
    const Filter& g = findFilter("gaussian");
    const FrameBuffers frame = syntheticFrame(8, 6);
    const Rect outside{4, 10, 0, 3};
    EXPECT_THROW(applyFilter(g, frame, {}, testing::inRegion(outside)), Error);
    const Rect empty{3, 3, 0, 3};
    EXPECT_THROW(applyFilter(g, frame, {}, testing::inRegion(empty)), Error);
    // Every filter that needs feature layers names the missing one.
    FrameBuffers bare(8, 6);
    for (const Filter* f : testing::runnableFilters()) {
        if (f->requiredLayers(resolveParams(*f, {})).empty()) {
            EXPECT_NO_THROW(applyFilter(*f, bare, {})) << f->name();
            continue;
        }
        try {
            applyFilter(*f, bare, {});
            ADD_FAILURE() << f->name() << " ran without its feature layers";
        } catch (const Error& e) {
            EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
        }
    }
}

}  // namespace
}  // namespace glint::denoise
