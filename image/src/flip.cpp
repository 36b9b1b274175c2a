// FLIP and HDR-FLIP (docs/metrics.md, "FLIP"). Equations from Andersson et al., "FLIP: A
// Difference Evaluator for Alternating Images", HPG 2020 (cited as "FLIP"), and Andersson et al.,
// "Visualizing Errors in Rendered High Dynamic Range Images", EG 2021 short ("HDR-FLIP"); the
// separated form of the filters follows the authors' note on separated convolutions.
#include "glint/image/flip.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/internal/simd.h"
#include "glint/image/io.h"

namespace glint {
namespace {

constexpr double kPi = 3.14159265358979323846;

// FLIP sec. 4: colour exponent q_c, redistribution knee p_c and target p_t, the edge detector's
// peak-to-trough width w (degrees) and feature exponent q_f.
constexpr float kQc = 0.7f;
constexpr float kPc = 0.4f;
constexpr float kPt = 0.95f;
constexpr double kFeatureWidth = 0.082;
constexpr float kQf = 0.5f;

// FLIP eq. 2 and Table 1: each opponent channel's contrast sensitivity as a sum of two Gaussians
// a1 sqrt(pi/b1) exp(-pi^2 r^2/b1) + a2 sqrt(pi/b2) exp(-pi^2 r^2/b2), r in degrees.
struct Csf {
    double a1, b1, a2, b2;
};
constexpr Csf kAchromatic{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kRedGreen{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kBlueYellow{34.1, 0.04, 13.5, 0.025};

// Linear sRGB (D65) to CIE XYZ, and the D65 white point.
constexpr double kRgbToXyz[3][3] = {
    {10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0},
    {2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0},
    {1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0}};
constexpr double kWhite[3] = {0.950428545, 1.0, 1.088900371};

// Luminance of linear sRGB (Rec. 709 weights), used for HDR-FLIP's exposure range.
float luminance(const float* rgb) {
    return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

// The per-pixel stage works on 8 pixels at a time (GCC vector extensions,
// glint/image/internal/simd.h): comparisons give lane masks, `select` picks per lane, bit casts
// reinterpret. The helpers take and return vectors by value but are always inlined, so no call's
// ABI depends on AVX: GCC's note about that ABI (-Wpsabi, given once for the file at its end) does
// not apply to them.
#pragma GCC diagnostic ignored "-Wpsabi"
using detail::VecF;
using detail::VecI;
typedef std::uint32_t VecU __attribute__((vector_size(32)));

[[gnu::always_inline]] inline VecF splat(float v) {
    return VecF{} + v;
}

[[gnu::always_inline]] inline VecF select(VecI mask, VecF a, VecF b) {
    return mask ? a : b;
}

[[gnu::always_inline]] inline VecF vmin(VecF a, VecF b) {
    return select(a < b, a, b);
}

[[gnu::always_inline]] inline VecF vmax(VecF a, VecF b) {
    return select(a > b, a, b);
}

[[gnu::always_inline]] inline VecF vabs(VecF a) {
    return select(a < 0.0f, -a, a);
}

/// Lane-wise square root (one vsqrtps: flip.cpp is built with -fno-math-errno).
[[gnu::always_inline]] inline VecF vsqrt(VecF v) {
    VecF r;
    for (int i = 0; i < 8; ++i) r[i] = std::sqrt(v[i]);
    return r;
}

/// Cube root of positive normal values to float precision without a library call or a branch:
/// Kahan's exponent-thirds first guess, then two Halley steps.
[[gnu::always_inline]] inline VecF cubeRoot(VecF v) {
    const VecU bits = (VecU)v / 3u + 709921077u;
    VecF y = (VecF)bits;
    for (int i = 0; i < 2; ++i) {
        const VecF y3 = y * y * y;
        y *= (y3 + 2.0f * v) / (2.0f * y3 + v);
    }
    return y;
}

/// log2 of positive normal values to about 1e-7 relative error, branch-free: the exponent plus
/// the natural log of the mantissa in [sqrt(1/2), sqrt(2)) by Cephes' logf polynomial.
[[gnu::always_inline]] inline VecF log2Approx(VecF x) {
    VecI bits = (VecI)x;
    VecI e = ((bits >> 23) & 0xff) - 127;
    bits = (bits & 0x007fffff) | 0x3f800000;
    VecF m = (VecF)bits;
    const VecI high = m > 1.41421356f;
    m = select(high, 0.5f * m, m);
    e -= high;  // a true mask is -1
    const VecF f = m - 1.0f, z = f * f;
    VecF p = splat(7.0376836292e-2f);
    for (const float c : {-1.1514610310e-1f, 1.1676998740e-1f, -1.2420140846e-1f, 1.4249322787e-1f,
                          -1.6668057665e-1f, 2.0000714765e-1f, -2.4999993993e-1f, 3.3333331174e-1f})
        p = p * f + c;
    const VecF ln = f + (p * f * z - 0.5f * z);
    return ln * 1.44269504089f + __builtin_convertvector(e, VecF);
}

/// 2^x to about 2e-7 relative error, branch-free; 0 below -126, x at most 127: 2^n for the
/// nearest integer n (by the 1.5 * 2^23 rounding trick) times Cephes' exp2f polynomial of the
/// rest in [-1/2, 1/2].
[[gnu::always_inline]] inline VecF exp2Approx(VecF x) {
    constexpr float kRound = 12582912.0f;
    const VecF clamped = vmin(vmax(x, splat(-126.0f)), splat(127.0f));
    const VecF n = (clamped + kRound) - kRound;
    const VecF f = clamped - n;
    VecF p = splat(1.535336188319500e-4f);
    for (const float c : {1.339887440266574e-3f, 9.618437357674640e-3f, 5.550332471162809e-2f,
                          2.402264791363012e-1f, 6.931472028550421e-1f, 1.0f})
        p = p * f + c;
    const VecF scale = (VecF)((__builtin_convertvector(n, VecI) + 127) << 23);
    return select(x < -126.0f, VecF{}, p * scale);
}

/// The colour transforms of the pipeline, with the XYZ-to-RGB inverse computed once.
struct ColorSpace {
    float toXyz[3][3];
    float toRgb[3][3];
    float white[3];
    float invWhite[3];

    ColorSpace() {
        const auto& m = kRgbToXyz;
        const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) {
                // Inverse = adjugate / determinant: cofactor of (c, r).
                const int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
                toRgb[r][c] = float((m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det);
                toXyz[r][c] = float(m[r][c]);
            }
        for (int c = 0; c < 3; ++c) {
            white[c] = float(kWhite[c]);
            invWhite[c] = float(1.0 / kWhite[c]);
        }
    }

    template <typename T>
    static void apply(const float (&m)[3][3], const T* in, T* out) {
        for (int r = 0; r < 3; ++r) out[r] = m[r][0] * in[0] + m[r][1] * in[1] + m[r][2] * in[2];
    }

    /// Linear RGB to the opponent space YCxCz (FLIP sec. 4.1: CIELab without the cube root).
    void rgbToYcxcz(const float* rgb, float* ycxcz) const {
        float xyz[3];
        apply(toXyz, rgb, xyz);
        for (int c = 0; c < 3; ++c) xyz[c] *= invWhite[c];
        ycxcz[0] = 116.0f * xyz[1] - 16.0f;
        ycxcz[1] = 500.0f * (xyz[0] - xyz[1]);
        ycxcz[2] = 200.0f * (xyz[1] - xyz[2]);
    }

    /// Filtered YCxCz back to linear RGB, clamped to the unit cube (FLIP sec. 4.1.1), then to
    /// the Hunt-adjusted L*a*b* space: a and b scaled by 0.01 L (FLIP sec. 4.1.2); 8 pixels.
    void ycxczToHuntLab(const VecF (&ycxcz)[3], VecF (&lab)[3]) const {
        const VecF y = (ycxcz[0] + 16.0f) / 116.0f;
        const VecF xyz[3] = {(y + ycxcz[1] / 500.0f) * white[0], y * white[1],
                             (y - ycxcz[2] / 200.0f) * white[2]};
        VecF rgb[3];
        apply(toRgb, xyz, rgb);
        for (VecF& v : rgb) v = vmin(vmax(v, VecF{}), splat(1.0f));
        rgbToHuntLab(rgb, lab);
    }

    /// Linear RGB to Hunt-adjusted CIELab, 8 pixels.
    void rgbToHuntLab(const VecF (&rgb)[3], VecF (&lab)[3]) const {
        constexpr float delta = 6.0f / 29.0f;
        constexpr float deltaCube = delta * delta * delta;
        constexpr float slope = 1.0f / (3.0f * delta * delta);
        VecF xyz[3];
        apply(toXyz, rgb, xyz);
        for (int c = 0; c < 3; ++c) {
            const VecF v = xyz[c] * invWhite[c];
            const VecF root = cubeRoot(vmax(v, splat(deltaCube)));
            xyz[c] = select(v > deltaCube, root, slope * v + 4.0f / 29.0f);
        }
        const VecF l = 116.0f * xyz[1] - 16.0f;
        lab[0] = l;
        lab[1] = 0.01f * l * 500.0f * (xyz[0] - xyz[1]);
        lab[2] = 0.01f * l * 200.0f * (xyz[1] - xyz[2]);
    }
};

const ColorSpace& colorSpace() {
    static const ColorSpace space;
    return space;
}

/// HyAB distance (FLIP eq. 4): city-block in L, Euclidean in (a, b); 8 pixels.
[[gnu::always_inline]] inline VecF hyab(const VecF (&a)[3], const VecF (&b)[3]) {
    const VecF da = a[1] - b[1], db = a[2] - b[2];
    return vabs(a[0] - b[0]) + vsqrt(da * da + db * db);
}

/// The 1D kernels at a viewing condition. The 2D spatial filters are Gaussians (Y, Cx) or a sum
/// of two Gaussians (Cz), each separable: Cz = cz1(x) cz1(y) + cz2(x) cz2(y).
struct Kernels {
    int spatialRadius = 0;
    std::vector<float> y, cx, cz1, cz2;
    int featureRadius = 0;
    std::vector<float> g, dg, ddg;  ///< Gaussian, its first and second derivative
};

Kernels makeKernels(double ppd) {
    Kernels k;
    // FLIP sec. 4.1.1: support of 3 standard deviations of the widest Gaussian (b = 0.04).
    const double widest = std::max({kAchromatic.b1, kRedGreen.b1, kBlueYellow.b1, kBlueYellow.b2});
    k.spatialRadius = int(std::ceil(3.0 * std::sqrt(widest / (2.0 * kPi * kPi)) * ppd));
    const int n = 2 * k.spatialRadius + 1;
    // The 1D factor of a sqrt(pi/b) exp(-pi^2 (x^2 + y^2)/b) is sqrt(a sqrt(pi/b)) exp(-pi^2
    // x^2/b).
    auto factor = [](double a, double b, double x) {
        return std::sqrt(a * std::sqrt(kPi / b)) * std::exp(-kPi * kPi * x * x / b);
    };
    std::vector<double> y(n), cx(n), cz1(n), cz2(n);
    double sy = 0, scx = 0, scz1 = 0, scz2 = 0;
    for (int i = 0; i < n; ++i) {
        const double x = (i - k.spatialRadius) / ppd;  // degrees
        sy += y[i] = factor(kAchromatic.a1, kAchromatic.b1, x);
        scx += cx[i] = factor(kRedGreen.a1, kRedGreen.b1, x);
        scz1 += cz1[i] = factor(kBlueYellow.a1, kBlueYellow.b1, x);
        scz2 += cz2[i] = factor(kBlueYellow.a2, kBlueYellow.b2, x);
    }
    // Each 2D filter sums to 1: Y and Cx are products of one normalised 1D factor; the Cz sum
    // of products has total scz1^2 + scz2^2.
    const double czNorm = std::sqrt(scz1 * scz1 + scz2 * scz2);
    for (int i = 0; i < n; ++i) {
        k.y.push_back(float(y[i] / sy));
        k.cx.push_back(float(cx[i] / scx));
        k.cz1.push_back(float(cz1[i] / czNorm));
        k.cz2.push_back(float(cz2[i] / czNorm));
    }

    // FLIP sec. 4.2: edge and point detectors, the first and second derivative of a Gaussian of
    // standard deviation w/2 degrees; positive and negative weights normalised to +1 and -1.
    const double sd = 0.5 * kFeatureWidth * ppd;
    k.featureRadius = int(std::ceil(3.0 * sd));
    const int m = 2 * k.featureRadius + 1;
    std::vector<double> g(m), dg(m), ddg(m);
    double sg = 0, dgPos = 0, dgNeg = 0, ddgPos = 0, ddgNeg = 0;
    for (int i = 0; i < m; ++i) {
        const double x = i - k.featureRadius;
        g[i] = std::exp(-x * x / (2.0 * sd * sd));
        dg[i] = -x * g[i];
        ddg[i] = (x * x / (sd * sd) - 1.0) * g[i];
        sg += g[i];
        (dg[i] > 0 ? dgPos : dgNeg) += std::fabs(dg[i]);
        (ddg[i] > 0 ? ddgPos : ddgNeg) += std::fabs(ddg[i]);
    }
    for (int i = 0; i < m; ++i) {
        k.g.push_back(float(g[i] / sg));
        k.dg.push_back(float(dg[i] / (dg[i] > 0 ? dgPos : dgNeg)));
        k.ddg.push_back(float(ddg[i] / (ddg[i] > 0 ? ddgPos : ddgNeg)));
    }
    return k;
}

/// Rational tone curves (k0 x^2 + k1 x + k2) / (k3 x^2 + k4 x + k5) (HDR-FLIP sec. 3).
std::array<double, 6> toneCurve(FlipToneMapper mapper) {
    switch (mapper) {
        case FlipToneMapper::Aces:
            // Narkowicz's ACES fit, with its 0.6 pre-exposure folded in.
            return {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.0, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};
        case FlipToneMapper::Hable: {
            // Hable 2010's filmic curve f(x) = ((x(Ax + CB) + DE) / (x(Ax + B) + DF)) - E/F at
            // exposure bias 2, divided by f(W) for white W = 11.2.
            const double A = 0.15, B = 0.50, C = 0.10, D = 0.20, E = 0.02, F = 0.30, W = 11.2;
            const double n0 = A * F - A * E, n1 = C * B * F - B * E;
            const double d0 = A * F, d1 = B * F, d2 = D * F * F;
            const double whiteScale = (d0 * W * W + d1 * W + d2) / (n0 * W * W + n1 * W);
            return {4.0 * n0 * whiteScale, 2.0 * n1 * whiteScale, 0.0, 4.0 * d0, 2.0 * d1, d2};
        }
        case FlipToneMapper::Reinhard:
            return {0.0, 1.0, 0.0, 0.0, 1.0, 1.0};
    }
    return {};
}

/// Maps the input to the linear RGB in [0, 1] that LDR-FLIP sees, a row at a time.
struct PixelTransform {
    bool hdr = false;
    FlipToneMapper mapper = FlipToneMapper::Aces;
    double scale = 1.0;  ///< 2^exposure
    std::array<double, 6> k{};

    /// Exposed values beyond this are at the tone curves' asymptote (clamped to 1); the cap
    /// keeps the rational curves finite and maps an overflowed exposure (NaN, Inf) to white.
    static double exposed(float v, double scale) {
        const double x = std::max(double(v), 0.0) * scale;
        return x < 1e30 ? x : 1e30;
    }

    /// Transforms `n` pixels of planar rows in place.
    void operator()(float* r, float* g, float* b, int n) const {
        float* rgb[3] = {r, g, b};
        if (!hdr) {
            for (float* c : rgb)
                for (int i = 0; i < n; ++i) c[i] = std::clamp(c[i], 0.0f, 1.0f);
            return;
        }
        // HDR-FLIP sec. 3: negative values are clipped, the exposure applied, the tone curve
        // (per channel; Reinhard's on luminance) and a clamp to [0, 1].
        const double s = scale;
        if (mapper == FlipToneMapper::Reinhard) {
            for (int i = 0; i < n; ++i) {
                const double x[3] = {exposed(r[i], s), exposed(g[i], s), exposed(b[i], s)};
                const double l = 0.2126 * x[0] + 0.7152 * x[1] + 0.0722 * x[2];
                for (int c = 0; c < 3; ++c)
                    rgb[c][i] = float(std::clamp(x[c] / (1.0 + l), 0.0, 1.0));
            }
            return;
        }
        for (float* c : rgb)
            for (int i = 0; i < n; ++i) {
                const double x = exposed(c[i], s);
                const double v = ((k[0] * x + k[1]) * x + k[2]) / ((k[3] * x + k[4]) * x + k[5]);
                c[i] = float(std::clamp(v, 0.0, 1.0));
            }
    }
};

// The convolutions accumulate blocks of kLanes outputs in registers over all taps, the taps in
// order, so that each output's bits do not depend on the blocking.
constexpr int kLanes = 64;

/// acc[i] += the sum over taps t of weights[t] times the 8 floats at src(t) + 8 i.
template <int N, typename Source>
[[gnu::always_inline]] inline void accumulate(const float* weights, int taps, Source src,
                                              VecF (&acc)[N]) {
    for (int t = 0; t < taps; ++t) {
        const float* p = src(t);
        const float wt = weights[t];
        for (int i = 0; i < N; ++i) {
            VecF v;
            detail::loadVec(v, p + 8 * i);
            acc[i] += wt * v;
        }
    }
}

/// Runs `block` over [0, width) in blocks of kLanes, then 8, then 1 (the scalar rest).
template <typename Block>
[[gnu::always_inline]] inline void blocks(int width, Block block) {
    int x = 0;
    for (; x + kLanes <= width; x += kLanes) block.template operator()<kLanes / 8>(x);
    for (; x + 8 <= width; x += 8) block.template operator()<1>(x);
    for (; x < width; ++x) block.template operator()<0>(x);
}

/// out[x] = sum_t weights[t] in[x + t] for x in [0, width): `in` holds a padded row, taps - 1
/// more values than `out`.
GLINT_SIMD_CLONES
void convolveRow(const float* in, const std::vector<float>& kernel, int width, float* out) {
    const float* weights = kernel.data();
    const int taps = int(kernel.size());
    blocks(width, [&]<int N>(int x) {
        if constexpr (N == 0) {
            float acc = 0.0f;
            for (int t = 0; t < taps; ++t) acc += weights[t] * in[x + t];
            out[x] = acc;
        } else {
            VecF acc[N] = {};
            accumulate(
                weights, taps, [&](int t) { return in + x + t; }, acc);
            for (int i = 0; i < N; ++i) detail::storeVec(out + x + 8 * i, acc[i]);
        }
    });
}

/// One term of a vertical filter: `kernel` down the columns of `plane`.
struct ColumnTerm {
    const float* plane;
    const std::vector<float>* kernel;
};

/// out[x] = the sum over terms[0, count) of their vertical convolutions at row y of planes of
/// width x height, clamped at their top and bottom rows.
GLINT_SIMD_CLONES
void convolveColumns(const ColumnTerm* terms, int count, int width, int height, int y, float* out) {
    blocks(width, [&]<int N>(int x) {
        VecF acc[N > 0 ? N : 1] = {};
        float scalar = 0.0f;
        for (int i = 0; i < count; ++i) {
            const float* weights = terms[i].kernel->data();
            const int taps = int(terms[i].kernel->size()), radius = taps / 2;
            auto src = [&](int t) {
                return terms[i].plane +
                       std::size_t(std::clamp(y + t - radius, 0, height - 1)) * width + x;
            };
            if constexpr (N == 0)
                for (int t = 0; t < taps; ++t) scalar += weights[t] * *src(t);
            else
                accumulate(weights, taps, src, acc);
        }
        if constexpr (N == 0)
            out[x] = scalar;
        else
            for (int i = 0; i < N; ++i) detail::storeVec(out + x + 8 * i, acc[i]);
    });
}

// The horizontally filtered planes of one image.
enum Plane { SpatialY, SpatialCx, SpatialCz1, SpatialCz2, FeatureD, FeatureDD, FeatureG, kPlanes };

/// The horizontally filtered planes of both inputs, allocated once for all exposures.
class FlipPlanes {
  public:
    FlipPlanes(int width, int height)
        : m_area(std::size_t(width) * height), m_data(new float[2 * kPlanes * m_area]) {}
    float* operator()(int input, int p) { return m_data.get() + (input * kPlanes + p) * m_area; }

  private:
    std::size_t m_area;
    std::unique_ptr<float[]> m_data;  // uninitialised: every value is written before read
};

/// Step 1 of LDR-FLIP for one row of one input: the transform, the opponent colours and the
/// grey of FLIP sec. 4.2, filtered horizontally (edges clamped) into the planes' row y.
GLINT_SIMD_CLONES
void filterRow(const float* src, int w, const PixelTransform& transform, const Kernels& k, int pad,
               std::vector<float>& scratch, float* const (&out)[kPlanes]) {
    const std::size_t n = std::size_t(w + 2 * pad);
    scratch.resize(7 * n);
    float* r = scratch.data();
    float *g = r + n, *b = g + n, *yRow = b + n, *cxRow = yRow + n, *czRow = cxRow + n,
          *grayRow = czRow + n;
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = src + 3 * std::clamp(int(i) - pad, 0, w - 1);
        r[i] = p[0];
        g[i] = p[1];
        b[i] = p[2];
    }
    transform(r, g, b, int(n));
    const ColorSpace& space = colorSpace();
    for (std::size_t i = 0; i < n; ++i) {
        const float rgb[3] = {r[i], g[i], b[i]};
        float ycxcz[3];
        space.rgbToYcxcz(rgb, ycxcz);
        yRow[i] = ycxcz[0];
        cxRow[i] = ycxcz[1];
        czRow[i] = ycxcz[2];
        grayRow[i] = (ycxcz[0] + 16.0f) / 116.0f;  // FLIP sec. 4.2: Y in [0, 1]
    }
    const int s = pad - k.spatialRadius, f = pad - k.featureRadius;
    convolveRow(yRow + s, k.y, w, out[SpatialY]);
    convolveRow(cxRow + s, k.cx, w, out[SpatialCx]);
    convolveRow(czRow + s, k.cz1, w, out[SpatialCz1]);
    convolveRow(czRow + s, k.cz2, w, out[SpatialCz2]);
    convolveRow(grayRow + f, k.dg, w, out[FeatureD]);
    convolveRow(grayRow + f, k.ddg, w, out[FeatureDD]);
    convolveRow(grayRow + f, k.g, w, out[FeatureG]);
}

/// FLIP sec. 4.1.2: the largest HyAB distance of the unit cube (green to blue), to the power q_c.
float maxColorError() {
    static const float cmax = [] {
        const VecF green[3] = {VecF{}, splat(1.0f), VecF{}},
                   blue[3] = {VecF{}, VecF{}, splat(1.0f)};
        VecF g[3], b[3];
        colorSpace().rgbToHuntLab(green, g);
        colorSpace().rgbToHuntLab(blue, b);
        return std::pow(hyab(g, b)[0], kQc);
    }();
    return cmax;
}

/// Step 2's per-pixel part for one row. `acc` holds 7 rows of `stride` values (a multiple of 8,
/// at least `w`) per input (reference, then image): the filtered Y, Cx, Cz and the edge (dx,
/// ddx) and point (dy, ddy) responses. Writes FLIP's error to `out` (the max with what it holds
/// when `keepMax`).
GLINT_SIMD_CLONES
void errorRow(const float* acc, int w, std::size_t stride, bool keepMax, float* out) {
    const ColorSpace& space = colorSpace();
    const float cmax = maxColorError();
    const float pccmax = kPc * cmax;
    for (int x = 0; x < w; x += 8) {
        // Hunt-adjusted L*a*b*, edge and point magnitudes of both inputs.
        VecF lab[2][3], edge[2], point[2];
        for (int input = 0; input < 2; ++input) {
            VecF q[7];
            for (int i = 0; i < 7; ++i)
                detail::loadVec(q[i], acc + std::size_t(input * 7 + i) * stride + x);
            space.ycxczToHuntLab({q[0], q[1], q[2]}, lab[input]);
            edge[input] = vsqrt(q[3] * q[3] + q[5] * q[5]);
            point[input] = vsqrt(q[4] * q[4] + q[6] * q[6]);
        }
        // FLIP eq. 4-5: HyAB distance, compressed, redistributed to [0, 1].
        const VecF distance = hyab(lab[0], lab[1]);
        const VecF compressed = exp2Approx(kQc * log2Approx(vmax(distance, splat(1e-30f))));
        const VecF c = select(distance > 0.0f, compressed, VecF{});
        const VecF below = c * (kPt / pccmax);
        const VecF above = kPt + (c - pccmax) / (cmax - pccmax) * (1.0f - kPt);
        const VecF color = select(c < pccmax, below, above);
        // FLIP eq. 8-9: the larger of the edge and point differences, to the power q_f.
        static_assert(kQf == 0.5f, "the feature exponent is taken as a square root");
        const VecF feature =
            vsqrt(vmax(vabs(edge[0] - edge[1]), vabs(point[0] - point[1])) / std::sqrt(2.0f));
        // FLIP eq. 10: color^(1 - feature), with 0^0 = 1 as pow has it.
        const VecF exponent = 1.0f - feature;
        const VecF powered = exp2Approx(exponent * log2Approx(vmax(color, splat(1e-30f))));
        const VecF error =
            select(color > 0.0f, powered, select(exponent == 0.0f, splat(1.0f), VecF{}));
        // Store all 8 lanes, or the ones left in the row.
        const int lanes = std::min(8, w - x);
        for (int i = 0; i < lanes; ++i)
            out[x + i] = keepMax ? std::max(out[x + i], error[i]) : error[i];
    }
}

/// One LDR-FLIP evaluation of two 3-channel images after `transform`; writes the map into
/// `map` (max with what it holds when `keepMax`).
void ldrFlip(const Image& image, const Image& reference, const PixelTransform& transform,
             const Kernels& k, FlipPlanes& planes, Image& map, bool keepMax) {
    const int w = image.width(), h = image.height();
    const Image* inputs[2] = {&reference, &image};
    const int pad = std::max(k.spatialRadius, k.featureRadius);

    // Step 1: opponent colours of each row, filtered horizontally.
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
        std::vector<float> scratch;
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int input = 0; input < 2; ++input) {
                float* out[kPlanes];
                for (int p = 0; p < kPlanes; ++p) out[p] = planes(input, p) + std::size_t(y) * w;
                filterRow(inputs[input]->row(y), w, transform, k, pad, scratch, out);
            }
    });

    // Step 2: vertical filtering, colour and feature differences, the FLIP error per pixel.
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 4), [&](const tbb::blocked_range<int>& rows) {
        // Per input: Y, Cx, Cz, dx, ddx, dy, ddy of one row; then L, a, b, edge, point.
        // Rows padded to whole blocks of 8 (zeros past w) for the 8-wide per-pixel stage.
        const std::size_t stride = (std::size_t(w) + 7) / 8 * 8;
        std::vector<float> acc(2 * 7 * stride);
        auto row = [&](int input, int q) {
            return acc.data() + std::size_t(input * 7 + q) * stride;
        };
        for (int y = rows.begin(); y != rows.end(); ++y) {
            for (int input = 0; input < 2; ++input) {
                auto vertical = [&](std::initializer_list<ColumnTerm> terms, int q) {
                    convolveColumns(terms.begin(), int(terms.size()), w, h, y, row(input, q));
                };
                vertical({{planes(input, SpatialY), &k.y}}, 0);
                vertical({{planes(input, SpatialCx), &k.cx}}, 1);
                vertical({{planes(input, SpatialCz1), &k.cz1}, {planes(input, SpatialCz2), &k.cz2}},
                         2);
                vertical({{planes(input, FeatureD), &k.g}}, 3);
                vertical({{planes(input, FeatureDD), &k.g}}, 4);
                vertical({{planes(input, FeatureG), &k.dg}}, 5);
                vertical({{planes(input, FeatureG), &k.ddg}}, 6);
            }
            errorRow(acc.data(), w, stride, keepMax, map.row(y));
        }
    });
}

std::string pixelText(int x, int y) {
    return "(" + std::to_string(x) + ", " + std::to_string(y) + ")";
}

/// Throws unless every value of `im` is finite (and, for LDR, in [0, 1]).
void checkValues(const Image& im, const char* name, bool hdr) {
    for (int y = 0; y < im.height(); ++y) {
        const float* p = im.row(y);
        for (int x = 0; x < im.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = p[3 * x + c];
                if (!std::isfinite(v))
                    throw Error(ErrorKind::InvalidArgument,
                                std::string("the ") + name + " has " +
                                    (std::isnan(v) ? "NaN" : "Inf") + " at pixel " +
                                    pixelText(x, y) + "; FLIP needs finite values",
                                {}, hdr ? "flip-hdr" : "flip-ldr");
                if (!hdr && !(v >= 0.0f && v <= 1.0f))
                    throw Error(ErrorKind::InvalidArgument,
                                std::string("the ") + name + " has " + std::to_string(v) +
                                    " at pixel " + pixelText(x, y) +
                                    ", outside [0, 1]: LDR-FLIP compares display values; use "
                                    "HDR-FLIP (flip-hdr) for radiance",
                                {}, "flip-ldr");
            }
    }
}

Image cropped(const Image& im, const Rect& r) {
    Image out(r.width(), r.height(), im.channels());
    for (int y = r.y0; y < r.y1; ++y)
        std::copy(im.row(y) + std::size_t(r.x0) * im.channels(),
                  im.row(y) + std::size_t(r.x1) * im.channels(), out.row(y - r.y0));
    return out;
}

}  // namespace

FlipExposureRange flipExposureRange(const Image& reference, FlipToneMapper toneMapper) {
    if (reference.channels() != 3 || reference.empty())
        throw Error(ErrorKind::InvalidArgument, "HDR-FLIP needs a non-empty RGB reference", {},
                    "flip-hdr");
    // HDR-FLIP sec. 3: the input x_max that the tone curve maps to t = 0.85, the larger root of
    // (k0 - t k3) x^2 + (k1 - t k4) x + (k2 - t k5) = 0.
    const std::array<double, 6> k = toneCurve(toneMapper);
    const double t = 0.85;
    const double a = k[0] - t * k[3], b = k[1] - t * k[4], c = k[2] - t * k[5];
    const double xMax =
        a == 0.0 ? -c / b : (-b + std::copysign(1.0, a) * std::sqrt(b * b - 4 * a * c)) / (2 * a);
    std::vector<float> lum(reference.pixelCount());
    for (std::size_t i = 0; i < lum.size(); ++i)
        lum[i] = luminance(reference.data().data() + 3 * i);
    const float yMax = *std::max_element(lum.begin(), lum.end());
    // The median as the authors take it: the element at n/2 of the sorted luminances.
    const std::size_t mid = lum.size() / 2;
    std::nth_element(lum.begin(), lum.begin() + std::ptrdiff_t(mid), lum.end());
    const float yMedian = lum[mid];
    if (!(yMedian > 0.0f))
        throw Error(ErrorKind::InvalidArgument,
                    "half or more of the reference is black (median luminance " +
                        std::to_string(yMedian) +
                        "), so HDR-FLIP's exposure range (brightest to median) is undefined; "
                        "give the exposure range explicitly",
                    {}, "flip-hdr");
    return {std::log2(xMax / yMax), std::log2(xMax / yMedian)};
}

FlipResult flip(const Image& image, const Image& reference, const FlipOptions& options) {
    const char* where = options.hdr ? "flip-hdr" : "flip-ldr";
    if (!image.sameShape(reference))
        throw Error(ErrorKind::InvalidArgument,
                    "image is " + std::to_string(image.width()) + "x" +
                        std::to_string(image.height()) + "x" + std::to_string(image.channels()) +
                        " but the reference is " + std::to_string(reference.width()) + "x" +
                        std::to_string(reference.height()) + "x" +
                        std::to_string(reference.channels()) + "; they must match",
                    {}, where);
    if (image.empty() || image.channels() != 3)
        throw Error(ErrorKind::InvalidArgument,
                    "FLIP compares non-empty RGB images, got " + std::to_string(image.channels()) +
                        " channels",
                    {}, where);
    if (!(options.pixelsPerDegree > 0.0 && options.pixelsPerDegree <= 1000.0))
        throw Error(ErrorKind::InvalidArgument,
                    "pixels per degree must be in (0, 1000], got " +
                        std::to_string(options.pixelsPerDegree),
                    {}, where);
    const Image* a = &image;
    const Image* b = &reference;
    Image ca, cb;
    if (options.crop) {
        const Rect r = *options.crop;
        if (r.empty() || intersect(r, image.bounds()) != r)
            throw Error(ErrorKind::InvalidArgument, "the crop is empty or not inside the image", {},
                        where);
        ca = cropped(image, r);
        cb = cropped(reference, r);
        a = &ca;
        b = &cb;
    }
    checkValues(*a, "image", options.hdr);
    checkValues(*b, "reference", options.hdr);

    const Kernels kernels = makeKernels(options.pixelsPerDegree);
    FlipResult result;
    result.map = Image(a->width(), a->height(), 1, 0.0f);
    FlipPlanes planes(a->width(), a->height());
    PixelTransform transform;
    transform.hdr = options.hdr;
    if (!options.hdr) {
        ldrFlip(*a, *b, transform, kernels, planes, result.map, false);
    } else {
        double start = 0.0, stop = 0.0;
        if (!options.startExposure || !options.stopExposure) {
            const FlipExposureRange range = flipExposureRange(*b, options.toneMapper);
            start = options.startExposure.value_or(range.start);
            stop = options.stopExposure.value_or(range.stop);
        } else {
            start = *options.startExposure;
            stop = *options.stopExposure;
        }
        if (!(std::isfinite(start) && std::isfinite(stop) && start <= stop))
            throw Error(ErrorKind::InvalidArgument,
                        "the exposure range must be finite with start <= stop, got " +
                            std::to_string(start) + " .. " + std::to_string(stop),
                        {}, where);
        const int count =
            options.exposures > 0 ? options.exposures : int(std::max(2.0, std::ceil(stop - start)));
        if (count > 256)
            throw Error(ErrorKind::InvalidArgument,
                        "the exposure range " + std::to_string(start) + " .. " +
                            std::to_string(stop) + " needs " + std::to_string(count) +
                            " exposures (at most 256)",
                        {}, where);
        transform.mapper = options.toneMapper;
        transform.k = toneCurve(options.toneMapper);
        // HDR-FLIP sec. 3: LDR-FLIP at evenly spaced exposures, the maximum per pixel.
        for (int i = 0; i < count; ++i) {
            const double exposure = count == 1 ? start : start + i * (stop - start) / (count - 1);
            transform.scale = std::exp2(exposure);
            ldrFlip(*a, *b, transform, kernels, planes, result.map, i > 0);
        }
        result.startExposure = start;
        result.stopExposure = stop;
        result.exposures = count;
    }
    // Mean: per-row sums added in order (the same value for any thread count).
    double total = 0.0;
    for (int y = 0; y < result.map.height(); ++y) {
        double rowSum = 0.0;
        const float* p = result.map.row(y);
        for (int x = 0; x < result.map.width(); ++x) rowSum += p[x];
        total += rowSum;
    }
    result.mean = total / double(result.map.pixelCount());
    return result;
}

Image flipColorMap(const Image& errors) {
    // matplotlib's magma (CC0), every 8th of its 256 entries and the last, sRGB-encoded.
    static constexpr float kMagma[33][3] = {
        {0.001462f, 0.000466f, 0.013866f}, {0.013708f, 0.011771f, 0.068667f},
        {0.039608f, 0.031090f, 0.133515f}, {0.074257f, 0.052017f, 0.202660f},
        {0.113094f, 0.065492f, 0.276784f}, {0.159018f, 0.068354f, 0.352688f},
        {0.211718f, 0.061992f, 0.418647f}, {0.265447f, 0.060237f, 0.461840f},
        {0.316654f, 0.071690f, 0.485380f}, {0.366012f, 0.090314f, 0.497960f},
        {0.414709f, 0.110431f, 0.504662f}, {0.463508f, 0.129893f, 0.507652f},
        {0.512831f, 0.148179f, 0.507648f}, {0.562866f, 0.165368f, 0.504692f},
        {0.613617f, 0.181811f, 0.498536f}, {0.664915f, 0.198075f, 0.488836f},
        {0.716387f, 0.214982f, 0.475290f}, {0.767398f, 0.233705f, 0.457755f},
        {0.816914f, 0.255895f, 0.436461f}, {0.863320f, 0.283729f, 0.412403f},
        {0.904281f, 0.319610f, 0.388137f}, {0.937221f, 0.364929f, 0.368567f},
        {0.960949f, 0.418323f, 0.359630f}, {0.976690f, 0.476226f, 0.364466f},
        {0.986700f, 0.535582f, 0.382210f}, {0.992785f, 0.594891f, 0.410283f},
        {0.996096f, 0.653659f, 0.446213f}, {0.997325f, 0.711848f, 0.488154f},
        {0.996898f, 0.769591f, 0.534892f}, {0.995131f, 0.827052f, 0.585701f},
        {0.992440f, 0.884330f, 0.640099f}, {0.989434f, 0.941470f, 0.697519f},
        {0.987053f, 0.991438f, 0.749504f}};
    Image out(errors.width(), errors.height(), 3);
    for (std::size_t i = 0; i < errors.pixelCount(); ++i) {
        const float e = errors.data()[i * errors.channels()];
        // Entry index 255 e along the table; knots at 0, 8, ..., 248 and 255.
        const float index = std::isfinite(e) ? std::clamp(e, 0.0f, 1.0f) * 255.0f : 0.0f;
        const int knot = std::min(int(index / 8.0f), 31);
        const float lo = float(knot * 8), hi = knot == 31 ? 255.0f : lo + 8.0f;
        const float t = std::clamp((index - lo) / (hi - lo), 0.0f, 1.0f);
        for (int c = 0; c < 3; ++c) {
            const float v = kMagma[knot][c] + t * (kMagma[knot + 1][c] - kMagma[knot][c]);
            out.data()[i * 3 + std::size_t(c)] = srgbDecode(v);
        }
    }
    return out;
}

}  // namespace glint
