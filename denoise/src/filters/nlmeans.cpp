// nlmeans — non-local means (Buades, Coll & Morel 2005) with the variance-normalised patch
// distance of Rousselle, Knaus & Zwicker 2012 ("Adaptive rendering with non-local means
// filtering", eqs. 4-6).
//
// Output u'_p = sum_q w(p,q) u_q / sum_q w(p,q) over the (2s+1)^2 search window, with
// w(p,q) = exp(-max(0, D(p,q))) and D the mean over the (2f+1)^2 patch offsets n and the three
// channels of the per-pixel distance
//   d = ((u_p - u_q)^2 - alpha (var_p + min(var_p, var_q))) / (eps + k^2 (var_p + var_q)),
// taken at p+n and q+n, with var the variance of the mean (layer "variance"), eps = 1e-10 and
// k the strength (Rousselle et al. use 0.45, the default). alpha = min(1, (k / 0.05)^2):
// Rousselle's full variance cancellation (alpha = 1) for k >= 0.05, fading out below so that
// k -> 0 tends to the identity.
// Without a variance layer a uniform per-channel variance is estimated from the whole frame
// (Immerkær 1996). D is computed for each search offset as a box filter of the per-pixel
// distance image (running sums), so the cost does not grow with the patch size.
// Pairs that fall outside the image or touch a missing (NaN/Inf) pixel add 0 to the patch
// sum (the sum is always divided by the full patch size); missing pixels get weight 0. A
// per-pixel distance is clamped to ±30 (2f+1)^2, so one outlier in a patch rejects it.
//
// Parameters:
//   patchRadius   f, 0 … 10 (7×7 patches: 3)
//   searchRadius  s, 1 … 30 (21×21 window: 10)
//   strength      k, 1e-4 … 10 (log); larger smooths more, k -> 0 is the identity
#include "filters/nlmeans.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "filters/factories.h"
#include "filters/filter_util.h"
#include "filters/nl_distance.h"

namespace glint::denoise {

namespace {

using detail::VecF;

// The opening block of this file, verbatim (glint-denoise list prints it).
constexpr std::string_view kDescription =
    R"(nlmeans — non-local means (Buades, Coll & Morel 2005) with the variance-normalised patch
distance of Rousselle, Knaus & Zwicker 2012 ("Adaptive rendering with non-local means
filtering", eqs. 4-6).

Output u'_p = sum_q w(p,q) u_q / sum_q w(p,q) over the (2s+1)^2 search window, with
w(p,q) = exp(-max(0, D(p,q))) and D the mean over the (2f+1)^2 patch offsets n and the three
channels of the per-pixel distance
  d = ((u_p - u_q)^2 - alpha (var_p + min(var_p, var_q))) / (eps + k^2 (var_p + var_q)),
taken at p+n and q+n, with var the variance of the mean (layer "variance"), eps = 1e-10 and
k the strength (Rousselle et al. use 0.45, the default). alpha = min(1, (k / 0.05)^2):
Rousselle's full variance cancellation (alpha = 1) for k >= 0.05, fading out below so that
k -> 0 tends to the identity.
Without a variance layer a uniform per-channel variance is estimated from the whole frame
(Immerkær 1996). D is computed for each search offset as a box filter of the per-pixel
distance image (running sums), so the cost does not grow with the patch size.
Pairs that fall outside the image or touch a missing (NaN/Inf) pixel add 0 to the patch
sum (the sum is always divided by the full patch size); missing pixels get weight 0. A
per-pixel distance is clamped to ±30 (2f+1)^2, so one outlier in a patch rejects it.

Parameters:
  patchRadius   f, 0 … 10 (7×7 patches: 3)
  searchRadius  s, 1 … 30 (21×21 window: 10)
  strength      k, 1e-4 … 10 (log); larger smooths more, k -> 0 is the identity)";

constexpr float kUnknownVariance = 1e30f;
constexpr float kFullCancellation = 0.05f;  // alpha = 1 from this strength up
constexpr int kTile = 64;                   // tiles on a global grid (reproducible ROI output)

enum Plane : int { U0, U1, U2, V0, V1, V2, M, kPlanes };

struct Packed {
    Rect rect;
    int stride = 0;
    std::array<std::vector<float>, kPlanes> planes;
    std::size_t index(int x, int y) const {
        return std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0);
    }
};

Packed pack(const FrameBuffers& frame, const Rect& rect, WorkContext& work) {
    Packed pk;
    pk.rect = rect;
    pk.stride = rect.width();
    const std::size_t size = std::size_t(pk.stride) * std::size_t(rect.height());
    for (auto& p : pk.planes) p.assign(size, 0.0f);
    const Image& color = frame.color();
    const Image* var = frame.find(Layer::Variance);
    const std::array<double, 3> uniform =
        var ? std::array<double, 3>{} : estimateNoiseVariance(color);
    const Rect inside = intersect(rect, color.bounds());
    work.parallelFor(
        inside.y0, inside.y1,
        [&](int y) {
            for (int x = inside.x0; x < inside.x1; ++x) {
                const std::size_t i = pk.index(x, y);
                const float* c = color.row(y) + std::size_t(x) * 3;
                const bool valid = detail::isFinitePixel(c, 3);
                for (int k = 0; k < 3; ++k) {
                    pk.planes[std::size_t(U0 + k)][i] = valid ? c[k] : 0.0f;
                    double v = var ? double((*var)(x, y, k)) : uniform[std::size_t(k)];
                    v = std::isfinite(v) ? std::clamp(v, 0.0, double(kUnknownVariance))
                                         : double(kUnknownVariance);
                    pk.planes[std::size_t(V0 + k)][i] = float(v);
                }
                pk.planes[M][i] = valid ? 1.0f : 0.0f;
            }
        },
        0);
    return pk;
}

struct Settings {
    int f = 3, s = 10;
    float k2 = 0.2f, alpha = 1.0f, cap = 1470.0f, invPatch = 1.0f / 49.0f;
};

// Scratch buffers of one tile.
struct TileScratch {
    std::vector<float> dist, vert, acc;
};

// Per-pixel distances of one row: `n` (a multiple of 8) pixels from plane index ip, partners
// at ip + offset (Rousselle et al. 2012, eq. 5, with the cancellation scaled by alpha).
GLINT_SIMD_CLONES
void distanceRow(const Packed& pk, std::size_t ip, std::ptrdiff_t offset, int n, const Settings& st,
                 float* out) {
    const auto& P = pk.planes;
    const detail::NlDistancePlanes pl{
        {P[std::size_t(U0)].data(), P[std::size_t(U0 + 1)].data(), P[std::size_t(U0 + 2)].data()},
        {P[std::size_t(V0)].data(), P[std::size_t(V0 + 1)].data(), P[std::size_t(V0 + 2)].data()},
        P[M].data()};
    detail::nlDistanceRow(pl, ip, offset, n, st.k2, st.alpha, st.cap, out);
}

// Vertical box sums: out[y][i] = sum_{j=y..y+2f} in[j][i] for y < rows, i < n (multiple of 8).
GLINT_SIMD_CLONES
void verticalBox(const float* in, int n, int rows, int f, float* out) {
    for (int i = 0; i < n; i += 8) {
        VecF acc{};
        for (int j = 0; j <= 2 * f; ++j) {
            VecF v;
            detail::loadVec(v, in + std::size_t(j) * n + i);
            acc += v;
        }
        detail::storeVec(out + i, acc);
        for (int y = 1; y < rows; ++y) {
            VecF enter, leave;
            detail::loadVec(enter, in + std::size_t(y + 2 * f) * n + i);
            detail::loadVec(leave, in + std::size_t(y - 1) * n + i);
            acc += enter - leave;
            detail::storeVec(out + std::size_t(y) * n + i, acc);
        }
    }
}

// Weights of one row from its horizontal patch sums, accumulated into acc (R, G, B, weight
// planes of `n` floats, n a multiple of 8).
GLINT_SIMD_CLONES
void accumulateRow(const Packed& pk, std::size_t iq, const float* patchSum, int n,
                   const Settings& st, float* acc, std::size_t accPlane) {
    const auto& P = pk.planes;
    for (int i = 0; i < n; i += 8) {
        VecF t, m, u;
        detail::loadVec(t, patchSum + i);
        t *= -st.invPatch;
        t = t > 0.0f ? (VecF{} + (0.0f)) : t;
        detail::expNegInPlace(t);
        detail::loadVec(m, &P[M][iq + std::size_t(i)]);
        t *= m;
        for (int c = 0; c < 3; ++c) {
            VecF a;
            detail::loadVec(a, acc + std::size_t(c) * accPlane + std::size_t(i));
            detail::loadVec(u, &P[std::size_t(U0 + c)][iq + std::size_t(i)]);
            detail::storeVec(acc + std::size_t(c) * accPlane + std::size_t(i), a + t * u);
        }
        VecF a;
        detail::loadVec(a, acc + 3 * accPlane + std::size_t(i));
        detail::storeVec(acc + 3 * accPlane + std::size_t(i), a + t);
    }
}

// Filters the tile with top-left (tx0, ty0) (on the global kTile grid, clipped to the image:
// tw × th pixels) into acc (4 planes of kTile × kTile).
void filterTile(const Packed& pk, int tx0, int ty0, int tw, int th, const Settings& st,
                TileScratch& sc) {
    const int f = st.f;
    const int n = (tw + 2 * f + 7) / 8 * 8;  // distance columns (tile plus patch margin), padded
    const int dh = th + 2 * f;
    const std::size_t accPlane = std::size_t(kTile) * kTile;
    sc.dist.assign(std::size_t(dh) * n, 0.0f);
    sc.vert.assign(std::size_t(th) * n, 0.0f);
    sc.acc.assign(4 * accPlane, 0.0f);
    std::vector<float> rowSum(std::size_t(tw + 8), 0.0f);
    for (int oy = -st.s; oy <= st.s; ++oy) {
        for (int ox = -st.s; ox <= st.s; ++ox) {
            const std::ptrdiff_t offset = std::ptrdiff_t(oy) * pk.stride + ox;
            // Per-pixel distance image over the tile plus the patch margin.
            for (int j = 0; j < dh; ++j)
                distanceRow(pk, pk.index(tx0 - f, ty0 - f + j), offset, n, st,
                            sc.dist.data() + std::size_t(j) * n);
            // Patch sums: vertical running sums, then horizontal running sums (box filter).
            verticalBox(sc.dist.data(), n, th, f, sc.vert.data());
            for (int y = 0; y < th; ++y) {
                const float* v = sc.vert.data() + std::size_t(y) * n;
                double run = 0.0;
                for (int i = 0; i <= 2 * f; ++i) run += v[i];
                rowSum[0] = float(run);
                for (int x = 1; x < tw; ++x) {
                    run += double(v[x + 2 * f]) - double(v[x - 1]);
                    rowSum[std::size_t(x)] = float(run);
                }
                const std::size_t iq = std::size_t(std::ptrdiff_t(pk.index(tx0, ty0 + y)) + offset);
                accumulateRow(pk, iq, rowSum.data(), (tw + 7) / 8 * 8, st,
                              sc.acc.data() + std::size_t(y) * kTile, accPlane);
            }
        }
    }
}

}  // namespace

std::array<double, 3> estimateNoiseVariance(const Image& image) {
    std::array<double, 3> var{};
    const int w = image.width(), h = image.height();
    if (w < 3 || h < 3 || image.channels() < 3) return var;
    std::array<double, 3> sum{};
    std::size_t n = 0;
    static constexpr int kMask[3][3] = {{1, -2, 1}, {-2, 4, -2}, {1, -2, 1}};
    for (int y = 1; y + 1 < h; ++y)
        for (int x = 1; x + 1 < w; ++x) {
            std::array<double, 3> conv{};
            bool finite = true;
            for (int j = -1; j <= 1 && finite; ++j)
                for (int i = -1; i <= 1; ++i) {
                    const float* p = image.row(y + j) + std::size_t(x + i) * image.channels();
                    finite = finite && detail::isFinitePixel(p, 3);
                    for (int c = 0; c < 3; ++c)
                        conv[std::size_t(c)] += kMask[j + 1][i + 1] * double(p[c]);
                }
            if (!finite) continue;
            for (int c = 0; c < 3; ++c) sum[std::size_t(c)] += std::fabs(conv[std::size_t(c)]);
            ++n;
        }
    if (n == 0) return var;
    for (int c = 0; c < 3; ++c) {
        // Immerkær 1996, eq. (9).
        const double sigma =
            std::sqrt(std::numbers::pi / 2.0) * sum[std::size_t(c)] / (6.0 * double(n));
        var[std::size_t(c)] = std::isfinite(sigma * sigma) ? sigma * sigma : 0.0;
    }
    return var;
}

NlMeansFilter::NlMeansFilter()
    : m_params{
          ParamSpec{"patchRadius", "patch radius (px)", 0, 10, 3, ParamScale::Linear, true,
                    "Patch radius f: patches are (2f+1)^2 pixels."}
              .soft(1, 3),
          ParamSpec{"searchRadius", "search radius (px)", 1, 30, 10, ParamScale::Linear, true,
                    "Search radius s: the search window is (2s+1)^2 pixels."}
              .soft(3, 10),
          ParamSpec{"strength", "strength k", 1e-4, 10, 0.45, ParamScale::Log, false,
                    "Filter strength k: larger smooths more; k -> 0 is the identity."}
              .soft(0.1, 2.0),
      } {}

std::string_view NlMeansFilter::description() const {
    return kDescription;
}

int NlMeansFilter::margin(const ParamValues& params) const {
    return detail::paramInt(params, "patchRadius") + detail::paramInt(params, "searchRadius");
}

Image NlMeansFilter::apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                           WorkContext& work) const {
    Settings st;
    st.f = detail::paramInt(params, "patchRadius");
    st.s = detail::paramInt(params, "searchRadius");
    const double k = detail::paramValue(params, "strength");
    st.k2 = float(k * k);
    st.alpha = float(std::min(1.0, (k / kFullCancellation) * (k / kFullCancellation)));
    const int patch = (2 * st.f + 1) * (2 * st.f + 1);
    st.cap = 30.0f * float(patch);
    st.invPatch = 1.0f / float(patch);

    // Tiles of the global grid that meet roi, clipped to the image; the packed region covers
    // them plus the margin and the 8-column read-ahead of the SIMD loops.
    const Rect bounds = frame.color().bounds();
    const int gx0 = roi.x0 / kTile, gx1 = (roi.x1 + kTile - 1) / kTile;
    const int gy0 = roi.y0 / kTile, gy1 = (roi.y1 + kTile - 1) / kTile;
    const int m = st.f + st.s;
    const Rect cells{gx0 * kTile, std::min(gx1 * kTile, bounds.x1), gy0 * kTile,
                     std::min(gy1 * kTile, bounds.y1)};
    const Packed pk =
        pack(frame, Rect{cells.x0 - m, cells.x1 + m + 16, cells.y0 - m, cells.y1 + m}, work);

    Image out(roi.width(), roi.height(), 3);
    // One index per tile of the grid (a tile is the unit of work and of cancellation); each
    // thread keeps its scratch buffers.
    const int tilesX = gx1 - gx0, tiles = tilesX * (gy1 - gy0);
    tbb::enumerable_thread_specific<TileScratch> scratch;
    work.expectWork(tiles);
    work.parallelFor(0, tiles, [&](int t) {
        TileScratch& sc = scratch.local();
        const int gx = gx0 + t % tilesX, gy = gy0 + t / tilesX;
        const int tx0 = gx * kTile, ty0 = gy * kTile;
        const int tw = std::min(kTile, bounds.x1 - tx0), th = std::min(kTile, bounds.y1 - ty0);
        filterTile(pk, tx0, ty0, tw, th, st, sc);
        const std::size_t plane = std::size_t(kTile) * kTile;
        const Rect part = intersect(Rect{tx0, tx0 + tw, ty0, ty0 + th}, roi);
        for (int y = part.y0; y < part.y1; ++y)
            for (int x = part.x0; x < part.x1; ++x) {
                const std::size_t i = std::size_t(y - ty0) * kTile + std::size_t(x - tx0);
                const float wsum = sc.acc[3 * plane + i];
                for (int c = 0; c < 3; ++c)
                    out(x - roi.x0, y - roi.y0, c) =
                        wsum > 0.0f ? sc.acc[std::size_t(c) * plane + i] / wsum : 0.0f;
            }
    });
    return out;
}

std::unique_ptr<Filter> makeNlMeansFilter() {
    return std::make_unique<NlMeansFilter>();
}

}  // namespace glint::denoise
