// The tile kernel of the "nfor" filter; the method and its sources are described in nfor.cpp.
//
// A tile is filtered in three steps over the tile grown by the window radius r (the grown tile,
// "E"): (1) the NL-means weight images, one per window offset; (2) per pixel p of E, the
// weighted moments of [1, f_q - f_p] and the colour over p's window, and the 8×8 normal
// equations solved by Cholesky; (3) per pixel q of the tile, the weighted average of the
// estimates that the fits of all windows containing q give at q. All loops run over 8-pixel
// vectors of planar rows.
#include "filters/nfor_kernel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

#include "filters/nl_distance.h"
#include "filters/simd.h"

namespace glint::denoise::detail {

namespace {

using P = NforPlanes;
constexpr int kF = P::kFeatures;
constexpr int kDims = kF + 1;  // regressors: 1 and the 7 centred features
// Moments of one window: sum w, sum w d (7), sum w d d^T (upper triangle, 28), sum w y (3),
// sum w d y^T (7 × 3).
constexpr int kMomD = 1, kMomDD = 8, kMomY = 36, kMomDY = 39, kMoments = 60;
constexpr int kBeta = kDims * 3;  // coefficient planes (j * 3 + c), then the validity plane

int roundUp8(int n) {
    return (n + 7) / 8 * 8;
}

// Geometry of one tile's grown region E.
struct Grown {
    int x0, y0, w, h, stride;  // stride: 8-aligned plus 8 spare columns for the gather's reads
};

// Per-pixel NL-means distances of one row of n (multiple of 8) pixels starting at plane index
// ip, partners at ip + offset (Rousselle, Knaus & Zwicker 2012, eq. 5, full cancellation).
GLINT_SIMD_CLONES
void distanceRow(const P& pk, std::size_t ip, std::ptrdiff_t offset, int n, float k2, float cap,
                 float* out) {
    const NlDistancePlanes pl{{pk.planes[P::G0], pk.planes[P::G1], pk.planes[P::G2]},
                              {pk.planes[P::GV0], pk.planes[P::GV1], pk.planes[P::GV2]},
                              pk.planes[P::V]};
    nlDistanceRow(pl, ip, offset, n, k2, 1.0f, cap, out);
}

// Step 1: the weight image of every window offset over E, w(p, p + o) = exp(-max(0, D)) times
// the validity of p, with D the patch mean of the per-pixel distances (box sums).
GLINT_SIMD_CLONES
void weightImages(const P& pk, const Grown& e, const NforSettings& st, NforScratch& sc) {
    const int r = st.r, f = st.f, side = 2 * r + 1;
    const int n = roundUp8(e.w + 2 * f), dh = e.h + 2 * f;
    const int patch = (2 * f + 1) * (2 * f + 1);
    const float cap = 30.0f * float(patch), invPatch = 1.0f / float(patch);
    const float tau = std::max(pk.typicalVariance, 1e-30f);
    const std::size_t plane = std::size_t(e.h) * std::size_t(e.stride);
    sc.weights.assign(plane * std::size_t(side * side), 0.0f);
    sc.dist.assign(std::size_t(dh) * std::size_t(n), 0.0f);
    sc.vert.assign(std::size_t(e.h) * std::size_t(n), 0.0f);
    for (int oy = -r; oy <= r; ++oy)
        for (int ox = -r; ox <= r; ++ox) {
            const std::ptrdiff_t offset = std::ptrdiff_t(oy) * pk.stride + ox;
            float* wImg = sc.weights.data() + plane * std::size_t((oy + r) * side + (ox + r));
            for (int j = 0; j < dh; ++j)
                distanceRow(pk, pk.index(e.x0 - f, e.y0 - f + j), offset, n, st.k2, cap,
                            sc.dist.data() + std::size_t(j) * std::size_t(n));
            // Patch sums: vertical sums over 2f + 1 rows, then horizontal ones. Each is summed
            // afresh (no running sums), so a pixel's weight depends only on its own patches.
            const float* dist = sc.dist.data();
            for (int y = 0; y < e.h; ++y) {
                float* v = sc.vert.data() + std::size_t(y) * std::size_t(n);
                std::copy_n(dist + std::size_t(y) * n, n, v);
                for (int j = 1; j <= 2 * f; ++j)
                    for (int i = 0; i < n; ++i) v[i] += dist[std::size_t(y + j) * n + i];
            }
            for (int y = 0; y < e.h; ++y) {
                const float* v = sc.vert.data() + std::size_t(y) * std::size_t(n);
                float* row = wImg + std::size_t(y) * std::size_t(e.stride);
                const float* valid = pk.at(P::V, pk.index(e.x0, e.y0 + y));
                std::copy_n(v, e.w, row);
                for (int i = 1; i <= 2 * f; ++i)
                    for (int x = 0; x < e.w; ++x) row[x] += v[x + i];
                for (int x = 0; x < e.w; ++x) row[x] *= -invPatch;
                const std::size_t ip = pk.index(e.x0, e.y0 + y);
                for (int x = 0; x < e.w; x += 8) {
                    VecF t, m, sp, sq;
                    loadVec(t, row + x);
                    t = t > 0.0f ? VecF{} : t;
                    expNegInPlace(t);
                    loadVec(m, valid + x);
                    // The variance-ratio factor (the emitter guard, nfor.cpp).
                    loadVec(sp, pk.at(P::GS, ip + std::size_t(x)));
                    loadVec(sq, pk.at(P::GS,
                                      std::size_t(std::ptrdiff_t(ip + std::size_t(x)) + offset)));
                    const VecF lo = sp < sq ? sp : sq, hi = sp < sq ? sq : sp;
                    VecF g = st.varianceRatio * (lo + tau) / (hi + tau);
                    g = g > 1.0f ? (VecF{} + 1.0f) : g;
                    storeVec(row + x, t * m * g);
                }
                std::fill(row + e.w, row + e.stride, 0.0f);
            }
        }
}

// The weighted sample of one pixel vector for one window offset: weight, centred features, colour.
struct Sample {
    VecF w;
    std::array<VecF, kF> d, wd;
    std::array<VecF, 3> y;
};

[[gnu::always_inline]] inline void loadSample(const P& pk, std::size_t a, std::ptrdiff_t offset,
                                              const float* w, Sample& s) {
    const std::size_t b = std::size_t(std::ptrdiff_t(a) + offset);
    VecF valid;
    loadVec(s.w, w);
    loadVec(valid, pk.at(P::V, b));
    s.w *= valid;
    for (int k = 0; k < kF; ++k) {
        VecF fq, fp;
        loadVec(fq, pk.at(P::F0 + k, b));
        loadVec(fp, pk.at(P::F0 + k, a));
        s.d[std::size_t(k)] = fq - fp;
        s.wd[std::size_t(k)] = s.w * s.d[std::size_t(k)];
    }
    for (int c = 0; c < 3; ++c) loadVec(s.y[std::size_t(c)], pk.at(P::Y0 + c, b));
}

// Adds the weighted moments of one row of E for two window offsets (n pixels, a multiple of 8;
// w2 may be a row of zeros): each accumulator is loaded and stored once per two offsets.
GLINT_SIMD_CLONES_V4
void momentsRow(const P& pk, std::size_t ip, std::ptrdiff_t offset1, const float* w1,
                std::ptrdiff_t offset2, const float* w2, int n, float* mom, std::size_t momStride) {
    auto add = [&](int m, int i, const VecF& value) {
        float* p = mom + std::size_t(m) * momStride + std::size_t(i);
        VecF a;
        loadVec(a, p);
        storeVec(p, a + value);
    };
    for (int i = 0; i < n; i += 8) {
        const std::size_t a = ip + std::size_t(i);
        Sample s, t;
        loadSample(pk, a, offset1, w1 + i, s);
        loadSample(pk, a, offset2, w2 + i, t);
        add(0, i, s.w + t.w);
        for (int k = 0, m = kMomDD; k < kF; ++k) {
            const std::size_t K = std::size_t(k);
            add(kMomD + k, i, s.wd[K] + t.wd[K]);
            for (int l = k; l < kF; ++l)
                add(m++, i, s.wd[K] * s.d[std::size_t(l)] + t.wd[K] * t.d[std::size_t(l)]);
        }
        for (int c = 0; c < 3; ++c) {
            const std::size_t C = std::size_t(c);
            add(kMomY + c, i, s.w * s.y[C] + t.w * t.y[C]);
            for (int k = 0; k < kF; ++k)
                add(kMomDY + k * 3 + c, i,
                    s.wd[std::size_t(k)] * s.y[C] + t.wd[std::size_t(k)] * t.y[C]);
        }
    }
}

// 4-wide double vectors for solving four windows' normal equations at once (lane l: window x + l).
typedef double VecD __attribute__((vector_size(32)));
typedef long long VecL __attribute__((vector_size(32)));
typedef float VecF4 __attribute__((vector_size(16)));

// ok <- ok & (v is finite), lane-wise: inf - inf and NaN - NaN are NaN.
[[gnu::always_inline]] inline void andFinite(VecL& ok, const VecD& v) {
    ok &= (v - v) == 0.0;
}

// Solves the ridge-regularised normal equations of the 4 windows whose moments start at m
// (stride s) into beta (kBeta + 1 planes of stride `bs`, at indices i … i + 3). A window without
// weight is invalid; one whose system is not positive definite falls back to the weighted mean.
// Every lane follows the same steps in double, so a window's result does not depend on its lane.
GLINT_SIMD_CLONES
void solveWindows4(const float* m, std::size_t s, double ridge, float* beta, std::size_t bs,
                   std::size_t i) {
    std::array<VecD, kMoments> M;
    for (int k = 0; k < kMoments; ++k) {
        VecF4 v;
        std::memcpy(&v, m + std::size_t(k) * s, sizeof v);
        M[std::size_t(k)] = __builtin_convertvector(v, VecD);
    }
    auto mom = [&](int k) -> const VecD& { return M[std::size_t(k)]; };
    const VecD sum = mom(0);
    // Normal matrix A = sum w x x^T with x = [1, d], ridge on the slopes; right sides B.
    std::array<std::array<VecD, kDims>, kDims> A{};
    std::array<std::array<VecD, 3>, kDims> B{};
    A[0][0] = sum;
    for (int k = 0, t = kMomDD; k < kF; ++k) {
        A[0][k + 1] = A[k + 1][0] = mom(kMomD + k);
        for (int l = k; l < kF; ++l, ++t) A[k + 1][l + 1] = A[l + 1][k + 1] = mom(t);
        A[k + 1][k + 1] += ridge * sum;
    }
    for (int c = 0; c < 3; ++c) {
        B[0][std::size_t(c)] = mom(kMomY + c);
        for (int k = 0; k < kF; ++k)
            B[std::size_t(k + 1)][std::size_t(c)] = mom(kMomDY + k * 3 + c);
    }
    // Cholesky A = L L^T in place (lower triangle); lanes that fail go on with garbage.
    VecL ok = sum > 0.0;
    andFinite(ok, sum);
    for (int j = 0; j < kDims; ++j) {
        VecD dj = A[j][j];
        for (int k = 0; k < j; ++k) dj -= A[j][k] * A[j][k];
        ok &= dj > 1e-12 * sum;
        andFinite(ok, dj);
        VecD ljj;
        for (int l = 0; l < 4; ++l) ljj[l] = dj[l] > 0.0 ? std::sqrt(dj[l]) : 1.0;
        A[j][j] = ljj;
        for (int i2 = j + 1; i2 < kDims; ++i2) {
            VecD v = A[i2][j];
            for (int k = 0; k < j; ++k) v -= A[i2][k] * A[j][k];
            A[i2][j] = v / ljj;
        }
    }
    std::array<std::array<VecD, 3>, kDims> X{};
    for (int c = 0; c < 3; ++c) {
        std::array<VecD, kDims> z{};
        for (int j = 0; j < kDims; ++j) {
            VecD v = B[std::size_t(j)][std::size_t(c)];
            for (int k = 0; k < j; ++k) v -= A[j][k] * z[std::size_t(k)];
            z[std::size_t(j)] = v / A[j][j];
        }
        for (int j = kDims - 1; j >= 0; --j) {
            VecD v = z[std::size_t(j)];
            for (int k = j + 1; k < kDims; ++k) v -= A[k][j] * X[std::size_t(k)][std::size_t(c)];
            X[std::size_t(j)][std::size_t(c)] = v / A[j][j];
        }
    }
    for (const auto& row : X)
        for (const VecD& v : row) andFinite(ok, v);
    // Per lane: the fit, the weighted mean, or nothing.
    for (int l = 0; l < 4; ++l) {
        const std::size_t at = i + std::size_t(l);
        const bool valid = sum[l] > 0.0 && std::isfinite(sum[l]);
        for (int j = 0; j < kDims; ++j)
            for (int c = 0; c < 3; ++c) {
                double v = 0.0;
                if (ok[l] != 0)
                    v = X[std::size_t(j)][std::size_t(c)][l];
                else if (valid && j == 0)
                    v = B[0][std::size_t(c)][l] / sum[l];
                beta[std::size_t(j * 3 + c) * bs + at] = float(v);
            }
        beta[std::size_t(kBeta) * bs + at] = valid ? 1.0f : 0.0f;
    }
}

// Step 2: the coefficients of every window centred in E (Bitterli et al. 2016, eq. 4, with a
// ridge on the slopes).
void fitWindows(const P& pk, const Grown& e, const NforSettings& st, NforScratch& sc) {
    const int r = st.r, side = 2 * r + 1;
    const std::size_t s = std::size_t(e.stride);
    const std::size_t plane = std::size_t(e.h) * s;
    const int n = roundUp8(e.w);
    sc.beta.assign(plane * std::size_t(kBeta + 1), 0.0f);
    sc.moments.assign(std::size_t(kMoments) * s, 0.0f);
    sc.zeros.assign(s, 0.0f);
    for (int y = 0; y < e.h; ++y) {
        std::fill(sc.moments.begin(), sc.moments.end(), 0.0f);
        const std::size_t ip = pk.index(e.x0, e.y0 + y);
        // The window offsets in pairs (the last paired with a zero weight row when odd).
        const int count = side * side;
        for (int o = 0; o < count; o += 2) {
            const int o2 = std::min(o + 1, count - 1);
            const float* w1 = sc.weights.data() + plane * std::size_t(o) + std::size_t(y) * s;
            const float* w2 = o + 1 < count
                                  ? sc.weights.data() + plane * std::size_t(o2) + std::size_t(y) * s
                                  : sc.zeros.data();
            const std::ptrdiff_t off1 = std::ptrdiff_t(o / side - r) * pk.stride + (o % side - r);
            const std::ptrdiff_t off2 = std::ptrdiff_t(o2 / side - r) * pk.stride + (o2 % side - r);
            momentsRow(pk, ip, off1, w1, off2, w2, n, sc.moments.data(), s);
        }
        for (int x = 0; x < e.w; x += 4)
            solveWindows4(sc.moments.data() + x, s, st.ridge, sc.beta.data(), plane,
                          std::size_t(y) * s + std::size_t(x));
    }
}

// Adds, for one tile row of n pixels (multiple of 8) and one window offset, the estimates of the
// windows centred at q - o at the pixels q (Bitterli et al. 2016, eq. 6: collaborative).
GLINT_SIMD_CLONES_V4
void gatherRow(const P& pk, std::size_t iq, std::ptrdiff_t offset, const float* w,
               const float* beta, std::size_t betaPlane, int n, float* acc, std::size_t accPlane) {
    for (int i = 0; i < n; i += 8) {
        const std::size_t q = iq + std::size_t(i), p = std::size_t(std::ptrdiff_t(q) - offset);
        VecF wt, fm;
        loadVec(wt, w + i);
        loadVec(fm, pk.at(P::FM, q));
        std::array<VecF, kF> d;
        for (int k = 0; k < kF; ++k) {
            VecF fq, fp;
            loadVec(fq, pk.at(P::F0 + k, q));
            loadVec(fp, pk.at(P::F0 + k, p));
            d[std::size_t(k)] = (fq - fp) * fm;
        }
        for (int c = 0; c < 3; ++c) {
            VecF est;
            loadVec(est, beta + std::size_t(c) * betaPlane + std::size_t(i));
            for (int k = 0; k < kF; ++k) {
                VecF b;
                loadVec(b, beta + std::size_t((k + 1) * 3 + c) * betaPlane + std::size_t(i));
                est += b * d[std::size_t(k)];
            }
            VecF a;
            loadVec(a, acc + std::size_t(c) * accPlane + std::size_t(i));
            storeVec(acc + std::size_t(c) * accPlane + std::size_t(i), a + wt * est);
        }
        VecF a;
        loadVec(a, acc + 3 * accPlane + std::size_t(i));
        storeVec(acc + 3 * accPlane + std::size_t(i), a + wt);
    }
}

}  // namespace

void nforTile(const NforPlanes& pk, int tx0, int ty0, int tw, int th, int tile,
              const NforSettings& st, NforScratch& sc, float* out) {
    const int r = st.r, side = 2 * r + 1;
    const Grown e{tx0 - r, ty0 - r, tw + 2 * r, th + 2 * r, roundUp8(tw + 2 * r) + 8};
    weightImages(pk, e, st, sc);
    fitWindows(pk, e, st, sc);

    // Step 3: per tile row, the weighted average of the window estimates.
    const std::size_t s = std::size_t(e.stride), plane = std::size_t(e.h) * s;
    const int n = roundUp8(tw);
    const std::size_t accPlane = std::size_t(n);
    std::vector<float> acc(4 * accPlane);
    for (int y = 0; y < th; ++y) {
        std::fill(acc.begin(), acc.end(), 0.0f);
        const std::size_t iq = pk.index(tx0, ty0 + y);
        for (int oy = -r; oy <= r; ++oy)
            for (int ox = -r; ox <= r; ++ox) {
                // The window centre p = q - o sits at (x + r - ox, y + r - oy) in E.
                const std::size_t pe = std::size_t(y + r - oy) * s + std::size_t(r - ox);
                const float* w =
                    sc.weights.data() + plane * std::size_t((oy + r) * side + (ox + r)) + pe;
                gatherRow(pk, iq, std::ptrdiff_t(oy) * pk.stride + ox, w, sc.beta.data() + pe,
                          plane, n, acc.data(), accPlane);
            }
        for (int x = 0; x < tw; ++x) {
            const float den = acc[3 * accPlane + std::size_t(x)];
            for (int c = 0; c < 3; ++c)
                out[std::size_t(c) * std::size_t(tile) * std::size_t(tile) +
                    std::size_t(y) * std::size_t(tile) + std::size_t(x)] =
                    den > 0.0f ? acc[std::size_t(c) * accPlane + std::size_t(x)] / den : 0.0f;
        }
    }
}

}  // namespace glint::denoise::detail
