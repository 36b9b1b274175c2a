// prefilter — variance-aware smoothing of the feature layers (albedo, normal, depth) before the
// main filters use them: motion blur and depth of field make features noisy, while the edges of
// static, in-focus objects are exact (zero variance) and must stay sharp.
//
// Each feature f with a variance-of-the-mean layer V is filtered with a joint bilateral whose
// range term is normalised by the pixels' variances (as Rousselle, Manzi & Zwicker 2013
// normalise feature distances by the variance):
//   f'_p = sum_q w f_q / sum_q w,
//   w(p,q) = exp(-|p-q|^2 / (2 sigmaSpatial^2))
//          * exp(-(1/2C) sum_c (f_p,c - f_q,c)^2
//                         / (varianceScale^2 (V_p,c + min(V_p,c, V_q,c)) + delta_c)),
// over the (2 radius + 1)^2 window (truncated at the border), delta_c = 1e-12 (1 + f_p,c^2).
// If p and q have the same true value, E (f_p - f_q)^2 = V_p + V_q; the denominator is that
// expectation with V_q capped at V_p (the variance cancellation of Rousselle, Knaus & Zwicker
// 2012, eq. 4): a neighbour that is exact (V_q = 0, e.g. the static side of a motion-blurred
// or antialiased edge) is judged against V_p alone, not 2 V_p, so it is not pulled in by
// differences the centre's own noise does not explain, and a noisier neighbour does not
// widen the test. A zero-variance pixel therefore only averages identical values (it is
// unchanged), a noisy pixel averages the neighbours within a few of its standard deviations. The
// variance layer is replaced by the variance of the weighted mean, sum w^2 V_q / (sum w)^2 (weights
// taken as fixed). A feature without a variance layer is left unchanged (nothing tells where it is
// noisy). Non-finite feature values get weight 0; a non-finite centre keeps only the spatial
// term; a non-finite variance counts as very large.
#include "glint/denoise/prefilter.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

using detail::VecF;

constexpr float kUnknownVariance = 1e30f;
constexpr float kRangeCap = 1e30f;  // exp(-1e30) is 0 already

// One feature layer as planes over the image plus a border of `pad` missing pixels on every
// side (and 8 more columns on the right for the SIMD tail): values, variances, validity, the
// scaled variances varianceScale^2 V_c and the centre terms delta_c per channel, and the
// channel average 1 / (2 C) per pixel (0 for a missing centre: only the spatial term stays).
struct FeaturePlanes {
    int pad = 0, stride = 0, channels = 0;
    std::vector<std::vector<float>> value, variance, scaledVariance, delta;
    std::vector<float> valid, centreFactor;
    std::size_t index(int x, int y) const {
        return std::size_t(y + pad) * std::size_t(stride) + std::size_t(x + pad);
    }
};

FeaturePlanes makePlanes(const Image& f, const Image& var, int pad, double k2, WorkContext& work) {
    FeaturePlanes fp;
    fp.pad = pad;
    fp.stride = f.width() + 2 * pad + 8;
    fp.channels = f.channels();
    const std::size_t size = std::size_t(fp.stride) * std::size_t(f.height() + 2 * pad);
    const std::size_t ch = std::size_t(fp.channels);
    fp.value.assign(ch, std::vector<float>(size, 0.0f));
    fp.variance.assign(ch, std::vector<float>(size, 0.0f));
    fp.scaledVariance.assign(ch, std::vector<float>(size, 0.0f));
    fp.delta.assign(ch, std::vector<float>(size, 1.0f));
    fp.valid.assign(size, 0.0f);
    fp.centreFactor.assign(size, 0.0f);
    work.parallelFor(
        0, f.height(),
        [&](int y) {
            for (int x = 0; x < f.width(); ++x) {
                const std::size_t i = fp.index(x, y);
                const bool finite = detail::isFinitePixel(f.row(y) + std::size_t(x) * ch, int(ch));
                fp.valid[i] = finite ? 1.0f : 0.0f;
                // A missing centre keeps only the spatial term (factor 0).
                fp.centreFactor[i] = finite ? float(1.0 / (2.0 * double(ch))) : 0.0f;
                for (std::size_t c = 0; c < ch; ++c) {
                    const double v = f(x, y, int(c));
                    const double vv = var(x, y, int(c));
                    const double sv = std::isfinite(vv)
                                          ? std::clamp(vv, 0.0, double(kUnknownVariance))
                                          : double(kUnknownVariance);
                    fp.value[c][i] = finite ? float(v) : 0.0f;
                    fp.variance[c][i] = float(sv);
                    fp.scaledVariance[c][i] = float(std::min(k2 * sv, double(kUnknownVariance)));
                    fp.delta[c][i] = finite ? float(1e-12 * (1.0 + v * v)) : 1.0f;
                }
            }
        },
        0);
    return fp;
}

// Filters 8 pixels from (x, y) of a C-channel feature; `spatial` holds the (2r+1)^2 spatial
// exponents (negative: skipped). Writes the C sums of w (f_q - f_p), the C sums of w^2 V_q and
// the weight sum, 8 lanes each, to out.
template <int C>
GLINT_SIMD_CLONES void filterBlock(const FeaturePlanes& fp, int x, int y, int r,
                                   const float* spatial, float* out) {
    const std::size_t ip = fp.index(x, y);
    VecF centre[C], centreVar[C], centreDelta[C], sum[C], sumVar[C], wsum{}, factor;
    detail::loadVec(factor, &fp.centreFactor[ip]);
    for (int c = 0; c < C; ++c) {
        detail::loadVec(centre[c], &fp.value[std::size_t(c)][ip]);
        detail::loadVec(centreVar[c], &fp.scaledVariance[std::size_t(c)][ip]);
        detail::loadVec(centreDelta[c], &fp.delta[std::size_t(c)][ip]);
        sum[c] = VecF{};
        sumVar[c] = VecF{};
    }
    const int d = 2 * r + 1;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const float sp = spatial[(dy + r) * d + dx + r];
            if (sp < 0.0f) continue;
            const std::size_t iq = fp.index(x + dx, y + dy);
            VecF diff[C], range{};
            for (int c = 0; c < C; ++c) {
                VecF q, vq;
                detail::loadVec(q, &fp.value[std::size_t(c)][iq]);
                detail::loadVec(vq, &fp.scaledVariance[std::size_t(c)][iq]);
                diff[c] = q - centre[c];
                // Expected squared difference of equal true values, V_q capped at V_p.
                const VecF den =
                    centreVar[c] + (vq < centreVar[c] ? vq : centreVar[c]) + centreDelta[c];
                const VecF term = diff[c] * diff[c] / den;
                // Clamped so that an overflow (inf) times a missing centre's 0 is not NaN.
                range += term < kRangeCap ? term : kRangeCap;
            }
            VecF w = -(sp + factor * range), m;
            detail::expNegInPlace(w);
            detail::loadVec(m, &fp.valid[iq]);
            w *= m;
            wsum += w;
            for (int c = 0; c < C; ++c) {
                VecF v;
                detail::loadVec(v, &fp.variance[std::size_t(c)][iq]);
                sum[c] += w * diff[c];
                sumVar[c] += w * w * v;
            }
        }
    for (int c = 0; c < C; ++c) {
        detail::storeVec(out + 8 * c, sum[c]);
        detail::storeVec(out + 8 * (C + c), sumVar[c]);
    }
    detail::storeVec(out + 16 * C, wsum);
}

// The prefilter's parameters, resolved.
struct Params {
    int radius;
    double sigmaSpatial, varianceScale;
};

// Filters one feature layer and its variance (same channel count) of the frame.
template <int C>
void filterFeature(const Image& f, const Image& var, const Params& params, Image& outF,
                   Image& outVar, WorkContext& work) {
    const int r = params.radius;
    const double invTwoSigmaS2 = 1.0 / (2.0 * params.sigmaSpatial * params.sigmaSpatial);
    const int d = 2 * r + 1;
    std::vector<float> spatial(std::size_t(d) * std::size_t(d));
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const double e = double(dx * dx + dy * dy) * invTwoSigmaS2;
            spatial[std::size_t((dy + r) * d + dx + r)] = e > 87.0 ? -1.0f : float(e);
        }
    const FeaturePlanes fp =
        makePlanes(f, var, r, params.varianceScale * params.varianceScale, work);
    work.parallelFor(0, f.height(), [&](int y) {
        float out[16 * C + 8];
        for (int x = 0; x < f.width(); x += 8) {
            filterBlock<C>(fp, x, y, r, spatial.data(), out);
            for (int l = 0; l < 8 && x + l < f.width(); ++l) {
                const float w = out[16 * C + l];
                for (int c = 0; c < C; ++c) {
                    // Centre plus the weighted mean difference: identical neighbours leave
                    // the centre bit-for-bit unchanged.
                    outF(x + l, y, c) =
                        w > 0.0f ? fp.value[std::size_t(c)][fp.index(x + l, y)] + out[8 * c + l] / w
                                 : 0.0f;
                    outVar(x + l, y, c) =
                        w > 0.0f ? std::min(out[8 * (C + c) + l] / (w * w), kUnknownVariance)
                                 : kUnknownVariance;
                }
            }
        }
    });
}

}  // namespace

const std::vector<ParamSpec>& prefilterParams() {
    static const std::vector<ParamSpec> specs{
        {"radius", "window radius (px)", 0, 100, 3, ParamScale::Linear, true,
         "Half window in pixels."},
        {"sigmaSpatial", "spatial sigma (px)", 1e-3, 1e3, 1.5, ParamScale::Log, false,
         "Spatial Gaussian standard deviation in pixels."},
        {"varianceScale", "variance scale", 1e-3, 1e3, 1.0, ParamScale::Log, false,
         "How many standard deviations of a pixel's own noise count as the same value."},
    };
    return specs;
}

FrameBuffers prefilterFeatures(const FrameBuffers& frame, const ParamValues& given,
                               const ProgressFn& progress) {
    const ParamValues resolved = resolveParams(prefilterParams(), given, "feature prefilter");
    const Params params{int(resolved.at("radius")), resolved.at("sigmaSpatial"),
                        resolved.at("varianceScale")};
    WorkContext work(progress);
    std::int64_t rows = 0;
    for (Layer layer : {Layer::Albedo, Layer::Normal, Layer::Depth}) {
        const std::optional<Layer> varLayer = varianceLayer(layer);
        if (frame.has(layer) && varLayer && frame.has(*varLayer)) rows += frame.height();
    }
    work.expectWork(rows);
    FrameBuffers out = frame;
    for (Layer layer : {Layer::Albedo, Layer::Normal, Layer::Depth}) {
        const std::optional<Layer> varLayer = varianceLayer(layer);
        if (!frame.has(layer) || !varLayer || !frame.has(*varLayer)) continue;
        Image f = frame.layer(layer), v = frame.layer(*varLayer);
        if (f.channels() == 3)
            filterFeature<3>(frame.layer(layer), frame.layer(*varLayer), params, f, v, work);
        else
            filterFeature<1>(frame.layer(layer), frame.layer(*varLayer), params, f, v, work);
        out.set(layer, std::move(f));
        out.set(*varLayer, std::move(v));
        out.metadata().extra[kFeaturesPrefilteredKey] = "1";
    }
    work.finish();
    return out;
}

}  // namespace glint::denoise
