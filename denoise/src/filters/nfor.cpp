// nfor — nonlinearly weighted first-order regression (Bitterli, Rousselle, Moon, Iglesias-Guitián,
// Adler, Mitchell, Jarosz & Novák 2016, "Nonlinearly Weighted First-order Regression for Denoising
// Monte Carlo Renderings").
//
// For every pixel p the colour over its (2r+1)^2 window is fitted by weighted least squares as an
// affine function of the 7 features x_q = [albedo RGB, normal XYZ, depth / mean |depth|] taken
// relative to the centre: y_q ~ b_p + B_p^T (x_q - x_p) (eq. 4), with a ridge lambda * sum w on
// the slopes and the 8×8 normal equations solved by Cholesky. The weights w(p,q) are NL-means
// weights exp(-max(0, D(p,q))) with the variance-normalised patch distance of Rousselle, Knaus &
// Zwicker 2012 (eq. 5, as nlmeans: (2f+1)^2 patches, strength k, full variance cancellation),
// times an emitter guard min(1, 4 (s_min + t) / (s_max + t)): s is the guide's variance averaged
// over channels and 3×3 pixels, s_min and s_max the pair's smaller and larger, t the frame's
// median s. A pixel partly covering a tiny bright emitter has a huge variance, and the distance,
// normalised by the sum of the variances, would let its dark neighbours accept it (and it them).
// Collaborative filtering (eq. 6): every window's fit gives an estimate at each pixel q of the
// window, and q's output is the w(p,q)-weighted average of the estimates of all windows
// containing it. First-order regression is exact on colour that is an affine function of the
// features (up to the ridge).
// With half buffers (glint::splitHalves) the filter cross-filters: half A is regressed with the
// weights computed from half B's colour and variance, B with A's, and the output is the mean of
// the two (Bitterli et al. 2016, sec. 5). Without them the weights come from the colour itself.
// Features are read from the frame as given: build a bank or auto with --prefilter to regress on
// prefiltered features. The paper's per-pixel choice between bandwidths is left to the bank and
// auto, which try several k.
// Missing (NaN/Inf) colour or feature pixels take no part in any weight or fit; their output is
// the weighted average of the estimates of the windows around them (features missing: the
// windows' intercepts). A feature beyond ±kMaxFeature (depth relative to its mean) or a colour
// beyond ±kMaxRadiance counts as missing too: no render writes one, and a window's float moments
// would overflow. Windows whose normal equations are not positive definite fall back to
// their weighted mean.
//
// Parameters:
//   windowRadius  r, 1 … 10 (9×9 windows: 4); outputs depend on the 2r + f pixels around.
//   patchRadius   f, 0 … 5 (3×3 patches: 1)
//   strength      k, 1e-3 … 10 (log; 1); larger weights more neighbours (smoother)
//   ridge         lambda, 1e-6 … 1 (log; 1e-3), in squared feature units: larger pulls slopes to 0
#include "filters/nfor.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>

#include "filters/factories.h"
#include "filters/filter_util.h"
#include "filters/nfor_kernel.h"
#include "filters/nlmeans.h"

namespace glint::denoise {

namespace {

using detail::NforPlanes;

// The opening block of this file, verbatim (glint-denoise list prints it).
constexpr std::string_view kDescription =
    R"(nfor — nonlinearly weighted first-order regression (Bitterli, Rousselle, Moon, Iglesias-Guitián,
Adler, Mitchell, Jarosz & Novák 2016, "Nonlinearly Weighted First-order Regression for Denoising
Monte Carlo Renderings").

For every pixel p the colour over its (2r+1)^2 window is fitted by weighted least squares as an
affine function of the 7 features x_q = [albedo RGB, normal XYZ, depth / mean |depth|] taken
relative to the centre: y_q ~ b_p + B_p^T (x_q - x_p) (eq. 4), with a ridge lambda * sum w on
the slopes and the 8×8 normal equations solved by Cholesky. The weights w(p,q) are NL-means
weights exp(-max(0, D(p,q))) with the variance-normalised patch distance of Rousselle, Knaus &
Zwicker 2012 (eq. 5, as nlmeans: (2f+1)^2 patches, strength k, full variance cancellation),
times an emitter guard min(1, 4 (s_min + t) / (s_max + t)): s is the guide's variance averaged
over channels and 3×3 pixels, s_min and s_max the pair's smaller and larger, t the frame's
median s. A pixel partly covering a tiny bright emitter has a huge variance, and the distance,
normalised by the sum of the variances, would let its dark neighbours accept it (and it them).
Collaborative filtering (eq. 6): every window's fit gives an estimate at each pixel q of the
window, and q's output is the w(p,q)-weighted average of the estimates of all windows
containing it. First-order regression is exact on colour that is an affine function of the
features (up to the ridge).
With half buffers (glint::splitHalves) the filter cross-filters: half A is regressed with the
weights computed from half B's colour and variance, B with A's, and the output is the mean of
the two (Bitterli et al. 2016, sec. 5). Without them the weights come from the colour itself.
Features are read from the frame as given: build a bank or auto with --prefilter to regress on
prefiltered features. The paper's per-pixel choice between bandwidths is left to the bank and
auto, which try several k.
Missing (NaN/Inf) colour or feature pixels take no part in any weight or fit; their output is
the weighted average of the estimates of the windows around them (features missing: the
windows' intercepts). A feature beyond ±1e4 (depth relative to its mean) or a colour beyond
±1e30 counts as missing.
Windows whose normal equations are not positive definite fall back to their weighted mean.

Parameters:
  windowRadius  r, 1 … 10 (9×9 windows: 4); outputs depend on the 2r + f pixels around.
  patchRadius   f, 0 … 5 (3×3 patches: 1)
  strength      k, 1e-3 … 10 (log; 1); larger weights more neighbours (smoother)
  ridge         lambda, 1e-6 … 1 (log; 1e-3), in squared feature units: larger pulls slopes to 0)";

constexpr float kUnknownVariance = 1e30f;
constexpr int kTile = 64;  // tiles on a global grid (reproducible ROI output)

// Storage of the packed planes: the colours and variances of one or two halves, the features
// and the masks, all over the same rectangle.
struct PackedFrame {
    Rect rect;
    int stride = 0;
    std::vector<std::vector<float>> store;
    std::vector<float> typicalVariance;  // per colour: NforPlanes::typicalVariance
    float* plane(std::size_t i) { return store[i].data(); }
};

// The largest feature (albedo, normal, depth / mean |depth|) and colour magnitudes the regression
// takes; beyond them a pixel is missing. A window's float sums of feature × colour then stay below
// 441 × 1e4 × kMaxRadiance (1e30), inside float. A render's albedo and normals are about 1.
constexpr float kMaxFeature = 1e4f;
// No render's depth exceeds about 3.5e9 (coordinates lie within ±1e9, docs/reliability.md): a
// larger one is left out of the depth scale, so that one absurd pixel does not flatten the depth
// feature of the whole frame (it is then missing, beyond kMaxFeature times the scale).
constexpr float kMaxDepth = 1e10f;

// Mean |depth| over the pixels of the whole frame with a finite depth of at most kMaxDepth (1
// when none or 0): the depth feature is scale-free and the same for every region of interest.
double meanAbsDepth(const Image& depth) {
    double sum = 0.0;
    std::size_t n = 0;
    for (float v : depth.data())
        if (std::fabs(v) <= kMaxDepth) {
            sum += std::fabs(double(v));
            ++n;
        }
    const double mean = n > 0 ? sum / double(n) : 0.0;
    return mean > 0.0 && std::isfinite(mean) ? mean : 1.0;
}

// The variance of `colours`, clamped to [0, kUnknownVariance] (non-finite: unknown), averaged
// over the channels and over the pixels of the image among the 3×3 around (NforPlanes::GS), over
// the whole frame; without a variance layer, the uniform estimate of the noise.
Image smoothedVariance(const FrameBuffers& colours, WorkContext& work) {
    const Image& color = colours.color();
    const Image* var = colours.find(Layer::Variance);
    const int w = color.width(), h = color.height();
    Image mean(w, h, 1), out(w, h, 1);
    std::array<double, 3> uniform{};
    if (!var) uniform = estimateNoiseVariance(color);
    work.parallelFor(
        0, h,
        [&](int y) {
            for (int x = 0; x < w; ++x) {
                double sum = 0.0;
                for (int c = 0; c < 3; ++c) {
                    double v = var ? double((*var)(x, y, c)) : uniform[std::size_t(c)];
                    v = std::isfinite(v) ? std::clamp(v, 0.0, double(kUnknownVariance))
                                         : double(kUnknownVariance);
                    sum += v;
                }
                mean(x, y, 0) = float(sum / 3.0);
            }
        },
        0);
    work.parallelFor(
        0, h,
        [&](int y) {
            for (int x = 0; x < w; ++x) {
                double sum = 0.0;
                int n = 0;
                for (int j = std::max(0, y - 1); j <= std::min(h - 1, y + 1); ++j)
                    for (int i = std::max(0, x - 1); i <= std::min(w - 1, x + 1); ++i, ++n)
                        sum += double(mean(i, j, 0));
                out(x, y, 0) = float(sum / double(n));
            }
        },
        0);
    return out;
}

// The median of the positive values of `plane` (0 when none is).
float medianPositive(const Image& plane) {
    std::vector<float> v;
    v.reserve(plane.data().size());
    for (float x : plane.data())
        if (x > 0.0f) v.push_back(x);
    if (v.empty()) return 0.0f;
    auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
}

// Packs `colours` (one frame, or halves A and B) and the features of `frame` over `rect`. The
// layout of `store`: per colour 3 colour and 3 variance planes, then 7 features, V and FM, then
// per colour its GS plane.
PackedFrame pack(const FrameBuffers& frame, const std::vector<const FrameBuffers*>& colours,
                 const Rect& rect, WorkContext& work) {
    PackedFrame pk;
    pk.rect = rect;
    pk.stride = rect.width();
    const std::size_t size = std::size_t(pk.stride) * std::size_t(rect.height());
    const std::size_t nc = colours.size(), oF = 6 * nc, oV = oF + 7, oFM = oV + 1, oGS = oFM + 1;
    pk.store.assign(oGS + nc, std::vector<float>(size, 0.0f));
    std::vector<Image> smoothed;
    for (std::size_t h = 0; h < nc; ++h) {
        smoothed.push_back(smoothedVariance(*colours[h], work));
        pk.typicalVariance.push_back(medianPositive(smoothed.back()));
    }
    std::vector<std::array<double, 3>> uniform(nc);
    for (std::size_t h = 0; h < nc; ++h)
        if (!colours[h]->find(Layer::Variance))
            uniform[h] = estimateNoiseVariance(colours[h]->color());
    const Image& albedo = frame.layer(Layer::Albedo);
    const Image& normal = frame.layer(Layer::Normal);
    const Image& depth = frame.layer(Layer::Depth);
    const float invDepth = float(1.0 / meanAbsDepth(depth));
    const Rect inside = intersect(rect, frame.color().bounds());
    work.parallelFor(
        inside.y0, inside.y1,
        [&](int y) {
            for (int x = inside.x0; x < inside.x1; ++x) {
                const std::size_t i =
                    std::size_t(y - rect.y0) * std::size_t(pk.stride) + std::size_t(x - rect.x0);
                std::array<float, 7> f{};
                for (int c = 0; c < 3; ++c) {
                    f[std::size_t(c)] = albedo(x, y, c);
                    f[std::size_t(3 + c)] = normal(x, y, c);
                }
                f[6] = depth(x, y, 0) * invDepth;
                const bool featuresOk = std::all_of(
                    f.begin(), f.end(), [](float v) { return std::fabs(v) <= kMaxFeature; });
                bool valid = featuresOk;
                for (std::size_t h = 0; h < nc; ++h) {
                    const Image& color = colours[h]->color();
                    const Image* var = colours[h]->find(Layer::Variance);
                    const float* c = color.row(y) + std::size_t(x) * 3;
                    const bool ok =
                        std::all_of(c, c + 3, [](float v) { return std::fabs(v) <= kMaxRadiance; });
                    valid = valid && ok;
                    for (int k = 0; k < 3; ++k) {
                        pk.store[6 * h + std::size_t(k)][i] = ok ? c[k] : 0.0f;
                        double v = var ? double((*var)(x, y, k)) : uniform[h][std::size_t(k)];
                        v = std::isfinite(v) ? std::clamp(v, 0.0, double(kUnknownVariance))
                                             : double(kUnknownVariance);
                        pk.store[6 * h + 3 + std::size_t(k)][i] = float(v);
                    }
                }
                for (std::size_t k = 0; k < 7; ++k) pk.store[oF + k][i] = featuresOk ? f[k] : 0.0f;
                pk.store[oV][i] = valid ? 1.0f : 0.0f;
                pk.store[oFM][i] = featuresOk ? 1.0f : 0.0f;
                for (std::size_t h = 0; h < nc; ++h) pk.store[oGS + h][i] = smoothed[h](x, y, 0);
            }
        },
        0);
    return pk;
}

// The kernel's view of one pass: weights from colour `guide`, regression of colour `target`.
NforPlanes passPlanes(PackedFrame& pk, std::size_t guide, std::size_t target, std::size_t nc) {
    NforPlanes p;
    p.rect = pk.rect;
    p.stride = pk.stride;
    for (int c = 0; c < 3; ++c) {
        p.planes[std::size_t(NforPlanes::G0 + c)] = pk.plane(6 * guide + std::size_t(c));
        p.planes[std::size_t(NforPlanes::GV0 + c)] = pk.plane(6 * guide + 3 + std::size_t(c));
        p.planes[std::size_t(NforPlanes::Y0 + c)] = pk.plane(6 * target + std::size_t(c));
    }
    for (int k = 0; k < NforPlanes::kFeatures; ++k)
        p.planes[std::size_t(NforPlanes::F0 + k)] = pk.plane(6 * nc + std::size_t(k));
    p.planes[NforPlanes::V] = pk.plane(6 * nc + 7);
    p.planes[NforPlanes::FM] = pk.plane(6 * nc + 8);
    p.planes[NforPlanes::GS] = pk.plane(6 * nc + 9 + guide);
    p.typicalVariance = pk.typicalVariance[guide];
    return p;
}

}  // namespace

NforFilter::NforFilter()
    : m_params{
          ParamSpec{"windowRadius", "window radius (px)", 1, 10, 4, ParamScale::Linear, true,
                    "Window radius r: each regression fits a (2r+1)^2 window."}
              .soft(3, 5),
          ParamSpec{"patchRadius", "patch radius (px)", 0, 5, 1, ParamScale::Linear, true,
                    "Patch radius f of the NL-means weights: patches are (2f+1)^2 pixels."}
              .soft(1, 3),
          ParamSpec{"strength", "strength k", 1e-3, 10, 1.0, ParamScale::Log, false,
                    "NL-means strength k: larger weights more neighbours (smoother)."}
              .soft(0.5, 4.0),
          ParamSpec{"ridge", "ridge lambda", 1e-6, 1, 1e-3, ParamScale::Log, false,
                    "Ridge on the feature slopes, in squared feature units: larger is flatter."}
              .soft(1e-5, 1e-2),
      } {}

std::string_view NforFilter::description() const {
    return kDescription;
}

std::vector<Layer> NforFilter::requiredLayers(const ParamValues& /*params*/) const {
    return {Layer::Albedo, Layer::Normal, Layer::Depth};
}

int NforFilter::margin(const ParamValues& params) const {
    // A window centred up to r pixels away reaches r further, and its weights read patches.
    return 2 * detail::paramInt(params, "windowRadius") + detail::paramInt(params, "patchRadius");
}

Image NforFilter::apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                        WorkContext& work) const {
    detail::NforSettings st;
    st.r = detail::paramInt(params, "windowRadius");
    st.f = detail::paramInt(params, "patchRadius");
    const double k = detail::paramValue(params, "strength");
    st.k2 = float(k * k);
    st.ridge = detail::paramValue(params, "ridge");

    // Cross-filtering needs the two halves; otherwise the frame is its own guide.
    std::pair<FrameBuffers, FrameBuffers> halves;
    std::vector<const FrameBuffers*> colours{&frame};
    if (frame.has(Layer::HalfColor)) {
        halves = splitHalves(frame);
        colours = {&halves.first, &halves.second};
    }

    // Tiles of the global grid that meet roi, clipped to the image; the packed region covers
    // them plus the margin and the 16-column read-ahead of the 8-wide loops.
    const Rect bounds = frame.color().bounds();
    const int gx0 = roi.x0 / kTile, gx1 = (roi.x1 + kTile - 1) / kTile;
    const int gy0 = roi.y0 / kTile, gy1 = (roi.y1 + kTile - 1) / kTile;
    const int m = 2 * st.r + st.f;
    const Rect cells{gx0 * kTile, std::min(gx1 * kTile, bounds.x1), gy0 * kTile,
                     std::min(gy1 * kTile, bounds.y1)};
    PackedFrame pk = pack(frame, colours,
                          Rect{cells.x0 - m, cells.x1 + m + 16, cells.y0 - m, cells.y1 + m}, work);
    const std::size_t nc = colours.size();
    std::vector<NforPlanes> passes;
    if (nc == 1)
        passes.push_back(passPlanes(pk, 0, 0, 1));
    else
        passes = {passPlanes(pk, 1, 0, 2), passPlanes(pk, 0, 1, 2)};  // A by B's weights, B by A's

    Image out(roi.width(), roi.height(), 3);
    const int tilesX = gx1 - gx0, tiles = tilesX * (gy1 - gy0);
    const std::size_t plane = std::size_t(kTile) * kTile;
    struct Scratch {
        detail::NforScratch kernel;
        std::vector<float> tile, sum;
    };
    tbb::enumerable_thread_specific<Scratch> scratch;
    work.expectWork(tiles);
    work.parallelFor(0, tiles, [&](int t) {
        Scratch& sc = scratch.local();
        const int tx0 = (gx0 + t % tilesX) * kTile, ty0 = (gy0 + t / tilesX) * kTile;
        const int tw = std::min(kTile, bounds.x1 - tx0), th = std::min(kTile, bounds.y1 - ty0);
        sc.sum.assign(3 * plane, 0.0f);
        sc.tile.assign(3 * plane, 0.0f);
        for (const NforPlanes& pass : passes) {
            detail::nforTile(pass, tx0, ty0, tw, th, kTile, st, sc.kernel, sc.tile.data());
            for (std::size_t i = 0; i < sc.sum.size(); ++i) sc.sum[i] += sc.tile[i];
        }
        const float scale = 1.0f / float(passes.size());
        const Rect part = intersect(Rect{tx0, tx0 + tw, ty0, ty0 + th}, roi);
        for (int y = part.y0; y < part.y1; ++y)
            for (int x = part.x0; x < part.x1; ++x) {
                const std::size_t i = std::size_t(y - ty0) * kTile + std::size_t(x - tx0);
                for (int c = 0; c < 3; ++c)
                    out(x - roi.x0, y - roi.y0, c) = sc.sum[std::size_t(c) * plane + i] * scale;
            }
    });
    return out;
}

std::unique_ptr<Filter> makeNforFilter() {
    return std::make_unique<NforFilter>();
}

}  // namespace glint::denoise
