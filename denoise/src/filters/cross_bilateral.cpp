// cross-bilateral — joint (cross) bilateral filter of the colour, steered by colour, albedo,
// normal and depth (Eisemann & Durand 2004, Petschnigg et al. 2004; the feature set and the
// variance normalisation follow Li, Wu & Chuang 2012 and Rousselle, Manzi & Zwicker 2013).
//
// Output c'_p = sum_q w(p,q) c_q / sum_q w(p,q) over the (2r+1)^2 window, with
//   w(p,q) = exp(-|p-q|^2 / (2 sigmaS^2) - sum_f D_f(p,q)),
//   D_f(p,q) = ||f_p - f_q||^2 / 2 * (1 / (2 sigma_f^2 + 2 V_f(p)) + 1 / (2 sigma_f^2 + 2 V_f(q)))
// for f in {colour, albedo, normal, depth}, where V_f is the sum over the feature's channels of
// its variance-of-the-mean layer (0 when the layer is absent): the mean of the two pixels'
// own normalisations (Rousselle et al. 2013 normalise by the centre's variance; the mean keeps
// w symmetric and needs no division per pair). Since E||f_p - f_q||^2 = ||true difference||^2
// + V_f(p) + V_f(q), noisy features count for less: a pure-noise difference between equally
// noisy pixels costs about 1 instead of growing without bound; without variances D_f is the
// usual ||f_p - f_q||^2 / (2 sigma_f^2). Depth is divided by the frame's
// mean |depth| first (so sigmaDepth is relative). The window is truncated at the border;
// missing (NaN/Inf) colour pixels get weight 0 and a missing centre drops its colour term;
// a non-finite feature value counts as unknown (its term vanishes).
//
// Parameters:
//   sigmaS       spatial sigma in pixels, 1e-6 … 1e6 (log)
//   radius       window radius; 0 = ceil(3 sigmaS); at most 100 (d = 31 is radius 15)
//   sigmaColor   colour sigma (radiance units), sigmaAlbedo, sigmaNormal, sigmaDepth (relative
//                depth), each 1e-6 … 1e6 (log)
// Needs the albedo, normal and depth layers; their variance layers are optional.
#include "filters/cross_bilateral.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "filters/bilateral.h"
#include "filters/factories.h"
#include "filters/filter_util.h"

namespace glint::denoise {

namespace {

using detail::VecF;

// The opening block of this file, verbatim (glint-denoise list prints it).
constexpr std::string_view kDescription =
    R"(cross-bilateral — joint (cross) bilateral filter of the colour, steered by colour, albedo,
normal and depth (Eisemann & Durand 2004, Petschnigg et al. 2004; the feature set and the
variance normalisation follow Li, Wu & Chuang 2012 and Rousselle, Manzi & Zwicker 2013).

Output c'_p = sum_q w(p,q) c_q / sum_q w(p,q) over the (2r+1)^2 window, with
  w(p,q) = exp(-|p-q|^2 / (2 sigmaS^2) - sum_f D_f(p,q)),
  D_f(p,q) = ||f_p - f_q||^2 / 2 * (1 / (2 sigma_f^2 + 2 V_f(p)) + 1 / (2 sigma_f^2 + 2 V_f(q)))
for f in {colour, albedo, normal, depth}, where V_f is the sum over the feature's channels of
its variance-of-the-mean layer (0 when the layer is absent): the mean of the two pixels'
own normalisations (Rousselle et al. 2013 normalise by the centre's variance; the mean keeps
w symmetric and needs no division per pair). Since E||f_p - f_q||^2 = ||true difference||^2
+ V_f(p) + V_f(q), noisy features count for less: a pure-noise difference between equally
noisy pixels costs about 1 instead of growing without bound; without variances D_f is the
usual ||f_p - f_q||^2 / (2 sigma_f^2). Depth is divided by the frame's
mean |depth| first (so sigmaDepth is relative). The window is truncated at the border;
missing (NaN/Inf) colour pixels get weight 0 and a missing centre drops its colour term;
a non-finite feature value counts as unknown (its term vanishes).

Parameters:
  sigmaS       spatial sigma in pixels, 1e-6 … 1e6 (log)
  radius       window radius; 0 = ceil(3 sigmaS); at most 100 (d = 31 is radius 15)
  sigmaColor   colour sigma (radiance units), sigmaAlbedo, sigmaNormal, sigmaDepth (relative
               depth), each 1e-6 … 1e6 (log)
Needs the albedo, normal and depth layers; their variance layers are optional.)";

// A variance standing for "unknown": large enough to silence a term, small enough that sums of
// a few stay finite in float.
constexpr float kUnknownVariance = 1e30f;

// Plane indices of the packed per-pixel data.
enum Plane : int { C0, C1, C2, VC, A0, A1, A2, VA, N0, N1, N2, VN, Z, VZ, M, kPlanes };

struct Packed {
    Rect rect;  // covered region in image coordinates (may reach outside the image)
    int stride = 0;
    std::array<std::vector<float>, kPlanes> planes;
    std::size_t index(int x, int y) const {
        return std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0);
    }
};

// Sum of a variance layer's channels at (x, y), sanitised: non-finite means unknown.
float varianceSum(const Image* var, int x, int y, int channels) {
    if (!var) return 0.0f;
    double s = 0.0;
    for (int c = 0; c < channels; ++c) s += double((*var)(x, y, c));
    if (!std::isfinite(s)) return kUnknownVariance;
    return float(std::clamp(s, 0.0, double(kUnknownVariance)));
}

// Copies a feature (values scaled by `scale`, variance by scale^2) into planes [first, first+n]
// at plane index i; a non-finite value makes the feature unknown at this pixel.
void packFeature(Packed& pk, std::size_t i, const Image& f, const Image* var, int x, int y,
                 int first, int channels, double scale) {
    const float* v = f.row(y) + std::size_t(x) * channels;
    bool finite = true;
    for (int c = 0; c < channels; ++c) {
        const double s = double(v[c]) / scale;
        finite = finite && std::isfinite(s);
        pk.planes[std::size_t(first + c)][i] = std::isfinite(s) ? float(s) : 0.0f;
    }
    float vs = varianceSum(var, x, y, channels);
    if (vs < kUnknownVariance) vs = float(std::min(double(vs) / (scale * scale), 1e30));
    pk.planes[std::size_t(first + channels)][i] = finite ? vs : kUnknownVariance;
}

double meanAbs(const Image& im) {
    double sum = 0.0;
    std::size_t n = 0;
    for (float v : im.data())
        if (std::isfinite(v)) {
            sum += std::fabs(double(v));
            ++n;
        }
    const double mean = n ? sum / double(n) : 0.0;
    return mean > 0.0 && std::isfinite(mean) ? mean : 1.0;
}

struct Sigmas {
    float color2, albedo2, normal2, depth2;  // 2 sigma_f^2 of each feature
};

// Replaces the variance sum V at index i of `plane` by 1 / (2 (2 sigma^2 + 2 V)), the pixel's
// half of the symmetrised normalisation.
void invertVariance(std::vector<float>& plane, std::size_t i, float twoSigma2) {
    plane[i] = float(0.25 / (0.5 * double(twoSigma2) + double(plane[i])));
}

Packed pack(const FrameBuffers& frame, const Rect& rect, const Sigmas& sig, WorkContext& work) {
    Packed pk;
    pk.rect = rect;
    pk.stride = rect.width() + 8;  // padding columns for the 8-wide tail
    const std::size_t size = std::size_t(pk.stride) * std::size_t(rect.height());
    for (auto& p : pk.planes) p.assign(size, 0.0f);
    const Image& color = frame.color();
    const Image& albedo = frame.layer(Layer::Albedo);
    const Image& normal = frame.layer(Layer::Normal);
    const Image& depth = frame.layer(Layer::Depth);
    const double depthScale = meanAbs(depth);
    const Rect inside = intersect(rect, color.bounds());
    work.parallelFor(
        inside.y0, inside.y1,
        [&](int y) {
            for (int x = inside.x0; x < inside.x1; ++x) {
                const std::size_t i = pk.index(x, y);
                const float* c = color.row(y) + std::size_t(x) * 3;
                const bool valid = detail::isFinitePixel(c, 3);
                for (int k = 0; k < 3; ++k) pk.planes[std::size_t(C0 + k)][i] = valid ? c[k] : 0.0f;
                pk.planes[VC][i] =
                    valid ? varianceSum(frame.find(Layer::Variance), x, y, 3) : kUnknownVariance;
                pk.planes[M][i] = valid ? 1.0f : 0.0f;
                packFeature(pk, i, albedo, frame.find(Layer::AlbedoVariance), x, y, A0, 3, 1.0);
                packFeature(pk, i, normal, frame.find(Layer::NormalVariance), x, y, N0, 3, 1.0);
                packFeature(pk, i, depth, frame.find(Layer::DepthVariance), x, y, Z, 1, depthScale);
                invertVariance(pk.planes[VC], i, sig.color2);
                invertVariance(pk.planes[VA], i, sig.albedo2);
                invertVariance(pk.planes[VN], i, sig.normal2);
                invertVariance(pk.planes[VZ], i, sig.depth2);
            }
        },
        0);
    // Outside the image the normalisations stay 0: those pixels have weight 0 anyway.
    return pk;
}

// Filters 8 output pixels starting at image column x of row y; `spatial` holds
// |p-q|^2 / (2 sigmaS^2) for the (2r+1)^2 offsets (negative: skipped, weight 0).
GLINT_SIMD_CLONES
void filterBlock(const Packed& pk, int x, int y, int r, const float* spatial,
                 float* sum /* 4 × 8 floats: R, G, B, weight */) {
    std::array<const float*, kPlanes> P;
    for (int k = 0; k < kPlanes; ++k) P[std::size_t(k)] = pk.planes[std::size_t(k)].data();
    const std::size_t ip = pk.index(x, y);
    VecF c0, c1, c2, vc, a0, a1, a2, va, n0, n1, n2, vn, z, vz;
    detail::loadVec(c0, &P[C0][ip]);
    detail::loadVec(c1, &P[C1][ip]);
    detail::loadVec(c2, &P[C2][ip]);
    detail::loadVec(vc, &P[VC][ip]);
    detail::loadVec(a0, &P[A0][ip]);
    detail::loadVec(a1, &P[A1][ip]);
    detail::loadVec(a2, &P[A2][ip]);
    detail::loadVec(va, &P[VA][ip]);
    detail::loadVec(n0, &P[N0][ip]);
    detail::loadVec(n1, &P[N1][ip]);
    detail::loadVec(n2, &P[N2][ip]);
    detail::loadVec(vn, &P[VN][ip]);
    detail::loadVec(z, &P[Z][ip]);
    detail::loadVec(vz, &P[VZ][ip]);
    VecF sr{}, sg{}, sb{}, sw{};
    const int d = 2 * r + 1;
    for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
            const float sp = spatial[(dy + r) * d + (dx + r)];
            if (sp < 0.0f) continue;
            const std::size_t iq = pk.index(x + dx, y + dy);
            VecF q0, q1, q2, qv, t, e;
            // Colour term.
            detail::loadVec(q0, &P[C0][iq]);
            detail::loadVec(q1, &P[C1][iq]);
            detail::loadVec(q2, &P[C2][iq]);
            detail::loadVec(qv, &P[VC][iq]);
            VecF d0 = c0 - q0, d1 = c1 - q1, d2 = c2 - q2;
            e = (d0 * d0 + d1 * d1 + d2 * d2) * (vc + qv) + sp;
            VecF w0 = q0, w1 = q1, w2 = q2;
            // Albedo term.
            detail::loadVec(q0, &P[A0][iq]);
            detail::loadVec(q1, &P[A1][iq]);
            detail::loadVec(q2, &P[A2][iq]);
            detail::loadVec(qv, &P[VA][iq]);
            d0 = a0 - q0, d1 = a1 - q1, d2 = a2 - q2;
            e += (d0 * d0 + d1 * d1 + d2 * d2) * (va + qv);
            // Normal term.
            detail::loadVec(q0, &P[N0][iq]);
            detail::loadVec(q1, &P[N1][iq]);
            detail::loadVec(q2, &P[N2][iq]);
            detail::loadVec(qv, &P[VN][iq]);
            d0 = n0 - q0, d1 = n1 - q1, d2 = n2 - q2;
            e += (d0 * d0 + d1 * d1 + d2 * d2) * (vn + qv);
            // Depth term.
            detail::loadVec(q0, &P[Z][iq]);
            detail::loadVec(qv, &P[VZ][iq]);
            d0 = z - q0;
            e += d0 * d0 * (vz + qv);
            // Weight, zero for missing neighbours.
            t = -e;
            detail::expNegInPlace(t);
            detail::loadVec(qv, &P[M][iq]);
            t *= qv;
            sr += t * w0;
            sg += t * w1;
            sb += t * w2;
            sw += t;
        }
    }
    detail::storeVec(sum, sr);
    detail::storeVec(sum + 8, sg);
    detail::storeVec(sum + 16, sb);
    detail::storeVec(sum + 24, sw);
}

}  // namespace

CrossBilateralFilter::CrossBilateralFilter()
    : m_params{
          ParamSpec{"sigmaS", "spatial sigma (px)", 1e-6, 1e6, 4.0, ParamScale::Log, false,
                    "Spatial standard deviation in pixels."}
              .soft(0.5, 5.0),
          ParamSpec{"radius", "window radius (px)", 0, kBilateralMaxRadius, 0,
                    ParamScale::Linear, true, "Window radius; 0 picks ceil(3 sigmaS)."}
              .soft(0, 0),
          ParamSpec{"sigmaColor", "colour sigma", 1e-6, 1e6, 0.5, ParamScale::Log, false,
                    "Colour range sigma (radiance units), widened by the colour variances."}
              .soft(0.05, 5.0),
          ParamSpec{"sigmaAlbedo", "albedo sigma", 1e-6, 1e6, 0.02, ParamScale::Log, false,
                    "Albedo range sigma, widened by the albedo variances."}
              .soft(0.005, 0.5),
          ParamSpec{"sigmaNormal", "normal sigma", 1e-6, 1e6, 0.05, ParamScale::Log, false,
                    "Normal range sigma, widened by the normal variances."}
              .soft(0.01, 1.0),
          ParamSpec{"sigmaDepth", "depth sigma (relative)", 1e-6, 1e6, 0.05, ParamScale::Log,
                    false, "Depth range sigma relative to the frame's mean depth."}
              .soft(0.005, 0.5),
      } {}

std::string_view CrossBilateralFilter::description() const {
    return kDescription;
}

int CrossBilateralFilter::margin(const ParamValues& params) const {
    return bilateralRadius(detail::paramValue(params, "sigmaS"),
                           detail::paramInt(params, "radius"));
}

Image CrossBilateralFilter::apply(const FrameBuffers& frame, const ParamValues& params,
                                  const Rect& roi, WorkContext& work) const {
    const double sigmaS = detail::paramValue(params, "sigmaS");
    const int r = margin(params);
    auto twoSq = [&](const char* name) {
        const double s = detail::paramValue(params, name);
        return float(std::clamp(2.0 * s * s, 1e-30, 1e30));
    };
    const Sigmas sig{twoSq("sigmaColor"), twoSq("sigmaAlbedo"), twoSq("sigmaNormal"),
                     twoSq("sigmaDepth")};

    // Spatial exponents; offsets whose weight underflows are skipped (marked -1).
    const int d = 2 * r + 1;
    std::vector<float> spatial(std::size_t(d) * d);
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const double t = std::hypot(double(dx), double(dy)) / sigmaS;
            const double e = 0.5 * t * t;
            spatial[std::size_t((dy + r) * d + dx + r)] = e > 87.0 ? -1.0f : float(e);
        }
    spatial[std::size_t(r * d + r)] = 0.0f;  // the centre always counts

    // Pack the window region (roi plus r, plus 8 columns so the last block can read ahead).
    const Packed pk =
        pack(frame, Rect{roi.x0 - r, roi.x1 + r + 8, roi.y0 - r, roi.y1 + r}, sig, work);

    const int w = roi.width();
    Image out(w, roi.height(), 3);
    work.parallelFor(roi.y0, roi.y1, [&](int y) {
        float sum[32];
        float* dst = out.row(y - roi.y0);
        for (int x = roi.x0; x < roi.x1; x += 8) {
            filterBlock(pk, x, y, r, spatial.data(), sum);
            for (int l = 0; l < 8 && x + l < roi.x1; ++l) {
                const float wsum = sum[24 + l];
                for (int c = 0; c < 3; ++c)
                    dst[std::size_t(x - roi.x0 + l) * 3 + c] =
                        wsum > 0.0f ? sum[c * 8 + l] / wsum : 0.0f;
            }
        }
    });
    return out;
}

std::unique_ptr<Filter> makeCrossBilateralFilter() {
    return std::make_unique<CrossBilateralFilter>();
}

}  // namespace glint::denoise
