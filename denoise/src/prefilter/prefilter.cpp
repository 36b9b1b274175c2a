// prefilter — variance-aware smoothing of the feature layers (albedo, normal, depth) before the
// main filters use them: motion blur and depth of field make features noisy, while the edges of
// static, in-focus objects are exact (zero variance) and must stay sharp.
//
// Each feature f with a variance-of-the-mean layer V is filtered with a joint bilateral whose
// range term is normalised by the centre pixel's variance (as Rousselle, Manzi & Zwicker 2013
// normalise feature distances by the centre's variance):
//   f'_p = sum_q w f_q / sum_q w,
//   w(p,q) = exp(-|p-q|^2 / (2 sigmaSpatial^2))
//          * exp(-(1/2C) sum_c (f_p,c - f_q,c)^2 / (varianceScale^2 2 V_p,c + delta_c)),
// over the (2 radius + 1)^2 window (truncated at the border), delta_c = 1e-12 (1 + f_p,c^2).
// A zero-variance pixel therefore only averages identical values (it is unchanged), a noisy
// pixel averages the neighbours within a few of its standard deviations. The variance layer is
// replaced by the variance of the weighted mean, sum w^2 V_q / (sum w)^2 (weights taken as
// fixed). A feature without a variance layer is left unchanged (nothing tells where it is
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

// One feature layer as planes over the image plus a border of `pad` missing pixels on every
// side (and 8 more columns on the right for the SIMD tail): values, variances, validity, and
// the centre normalisation 1 / (2 C (varianceScale^2 2 V_p,c + delta_c)) per channel.
struct FeaturePlanes {
    int pad = 0, stride = 0, channels = 0;
    std::vector<std::vector<float>> value, variance, invDen;
    std::vector<float> valid;
    std::size_t index(int x, int y) const {
        return std::size_t(y + pad) * std::size_t(stride) + std::size_t(x + pad);
    }
};

FeaturePlanes makePlanes(const Image& f, const Image& var, int pad, double k2) {
    FeaturePlanes fp;
    fp.pad = pad;
    fp.stride = f.width() + 2 * pad + 8;
    fp.channels = f.channels();
    const std::size_t size = std::size_t(fp.stride) * std::size_t(f.height() + 2 * pad);
    const std::size_t ch = std::size_t(fp.channels);
    fp.value.assign(ch, std::vector<float>(size, 0.0f));
    fp.variance.assign(ch, std::vector<float>(size, 0.0f));
    fp.invDen.assign(ch, std::vector<float>(size, 0.0f));
    fp.valid.assign(size, 0.0f);
    detail::parallelRows(0, f.height(), [&](int y) {
        for (int x = 0; x < f.width(); ++x) {
            const std::size_t i = fp.index(x, y);
            const bool finite = detail::isFinitePixel(f.row(y) + std::size_t(x) * ch, int(ch));
            fp.valid[i] = finite ? 1.0f : 0.0f;
            for (std::size_t c = 0; c < ch; ++c) {
                const double v = f(x, y, int(c));
                const double vv = var(x, y, int(c));
                const double sv = std::isfinite(vv) ? std::clamp(vv, 0.0, double(kUnknownVariance))
                                                    : double(kUnknownVariance);
                fp.value[c][i] = finite ? float(v) : 0.0f;
                fp.variance[c][i] = float(sv);
                // A missing centre keeps only the spatial term (normalisation 0).
                fp.invDen[c][i] =
                    finite
                        ? float(1.0 / (2.0 * double(ch) * (k2 * 2.0 * sv + 1e-12 * (1.0 + v * v))))
                        : 0.0f;
            }
        }
    });
    return fp;
}

// Filters 8 pixels from (x, y) of a C-channel feature; `spatial` holds the (2r+1)^2 spatial
// exponents (negative: skipped). Writes the C sums of w (f_q - f_p), the C sums of w^2 V_q and
// the weight sum, 8 lanes each, to out.
template <int C>
GLINT_SIMD_CLONES void filterBlock(const FeaturePlanes& fp, int x, int y, int r,
                                   const float* spatial, float* out) {
    const std::size_t ip = fp.index(x, y);
    VecF centre[C], inv[C], sum[C], sumVar[C], wsum{};
    for (int c = 0; c < C; ++c) {
        detail::loadVec(centre[c], &fp.value[std::size_t(c)][ip]);
        detail::loadVec(inv[c], &fp.invDen[std::size_t(c)][ip]);
        sum[c] = VecF{};
        sumVar[c] = VecF{};
    }
    const int d = 2 * r + 1;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const float sp = spatial[(dy + r) * d + dx + r];
            if (sp < 0.0f) continue;
            const std::size_t iq = fp.index(x + dx, y + dy);
            VecF diff[C], e = VecF{} + sp;
            for (int c = 0; c < C; ++c) {
                VecF q;
                detail::loadVec(q, &fp.value[std::size_t(c)][iq]);
                diff[c] = q - centre[c];
                e += diff[c] * diff[c] * inv[c];
            }
            VecF w = -e, m;
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

// Filters one feature layer and its variance (same channel count) of the frame.
template <int C>
void filterFeature(const Image& f, const Image& var, const PrefilterParams& params, Image& outF,
                   Image& outVar) {
    const int r = params.radius;
    const double invTwoSigmaS2 = 1.0 / (2.0 * params.sigmaSpatial * params.sigmaSpatial);
    const int d = 2 * r + 1;
    std::vector<float> spatial(std::size_t(d) * std::size_t(d));
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const double e = double(dx * dx + dy * dy) * invTwoSigmaS2;
            spatial[std::size_t((dy + r) * d + dx + r)] = e > 87.0 ? -1.0f : float(e);
        }
    const FeaturePlanes fp = makePlanes(f, var, r, params.varianceScale * params.varianceScale);
    detail::parallelRows(0, f.height(), [&](int y) {
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

void checkParam(bool ok, const std::string& what) {
    if (!ok) throw Error(ErrorKind::InvalidArgument, what, {}, "feature prefilter");
}

}  // namespace

FrameBuffers prefilterFeatures(const FrameBuffers& frame, const PrefilterParams& params) {
    checkParam(params.radius >= 0 && params.radius <= 100,
               "radius = " + std::to_string(params.radius) + " must be in [0, 100]");
    checkParam(std::isfinite(params.sigmaSpatial) && params.sigmaSpatial >= 1e-3 &&
                   params.sigmaSpatial <= 1e3,
               "sigmaSpatial = " + std::to_string(params.sigmaSpatial) + " must be in [1e-3, 1e3]");
    checkParam(
        std::isfinite(params.varianceScale) && params.varianceScale >= 1e-3 &&
            params.varianceScale <= 1e3,
        "varianceScale = " + std::to_string(params.varianceScale) + " must be in [1e-3, 1e3]");
    FrameBuffers out = frame;
    for (Layer layer : {Layer::Albedo, Layer::Normal, Layer::Depth}) {
        const std::optional<Layer> varLayer = varianceLayer(layer);
        if (!frame.has(layer) || !varLayer || !frame.has(*varLayer)) continue;
        Image f = frame.layer(layer), v = frame.layer(*varLayer);
        if (f.channels() == 3)
            filterFeature<3>(frame.layer(layer), frame.layer(*varLayer), params, f, v);
        else
            filterFeature<1>(frame.layer(layer), frame.layer(*varLayer), params, f, v);
        out.set(layer, std::move(f));
        out.set(*varLayer, std::move(v));
    }
    return out;
}

}  // namespace glint::denoise
