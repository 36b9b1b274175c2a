// The exact bilateral filter with symmetric pair evaluation: the Tomasi & Manduchi 1998 weight is
// symmetric, w(p, q) = w(q, p) (same spatial distance, same colour distance), so each pair of
// pixels needs one exp2 and its weight is added to both pixels' sums. That halves the dominant
// cost of the brute-force filter (distance + exp per window pixel) while every output keeps the
// full square window.
//
// Layout. The roi's rows are cut into bands of kBandRows (at least 4 radius) rows, fixed in image
// coordinates, one TBB task each, so the summation order and the result do not depend on the
// thread count. Inside a band the pairs (p, p + d) with d in the lower half window (dy >= 1) are
// enumerated row by row, p over the roi's columns grown by the radius (those p are the partners
// of roi pixels):
//   - both p and q = p + d in the band: one weight, added to p's and q's sums ("both");
//   - q below the band: added to p only (the next band adds it to q itself);
//   - p in the radius rows above the band ("pre-rows"), q in the band: added to q only.
// The centre row (dy = 0) of each band row is summed one-sided in registers. Sums of the rows in
// flight live in a ring of radius + 1 rows (planes r, g, b, weight); a row is normalised and
// written as soon as the enumeration has passed it. Loops run 8 pixels wide along a row for one
// offset d, so consecutive loads and stores of the sums never overlap (no store-forwarding
// stalls); a row is processed in tiles of kTileColumns columns to keep the data in L1.
//
// Non-finite policy: missing neighbours get weight 0 through the validity plane on both sides.
// A missing *centre* must drop its range term, which the shared pair weight cannot do, so a band
// with a missing pixel inside the roi is computed by the one-sided kernel instead.
#include <algorithm>
#include <cmath>

#include "filters/bilateral_kernel.h"
#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

constexpr int kBandRows = 64;      // minimum band height (the band is at least 4 radius high)
constexpr int kTileColumns = 128;  // p columns per tile

// One window offset of the lower half (dy >= 1) or of the centre row (dy = 0).
struct Tap {
    int dx = 0;
    int dy = 0;
    float s = 0.0f;  // spatialExponent(dx, dy)
};

// Sums of the rows in flight: planes (r, g, b, weight) of `rows` rows of `stride` floats each;
// image row y lives in ring row y mod rows. Column x lives at index x - x0.
struct SumRing {
    int rows = 0;
    int stride = 0;
    int x0 = 0;
    std::vector<float> data;

    float* at(int plane, int y, int x) {
        const std::size_t row = std::size_t(plane) * std::size_t(rows) + std::size_t(y % rows);
        return data.data() + row * std::size_t(stride) + std::size_t(x - x0);
    }
};

// Everything one band needs (shared, read-only).
struct ExactContext {
    const PlanarPlanes* planes = nullptr;
    Rect roi;
    int radius = 0;
    int imageHeight = 0;
    int px0 = 0, px1 = 0;  // columns of the p pixels (roi grown by radius, clipped to the image)
    float k = 0.0f;
    std::vector<Tap> lower;   // dy >= 1, row-major, weight not identically 0
    std::vector<Tap> centre;  // dy = 0, including (0, 0)
};

// Pointers to the four planes (r, g, b, valid or weight) at one position.
struct Quad {
    const float* c[4];
};
struct SumQuad {
    float* a[4];
};

// Pairs (p, p + d) for one offset d over n p-pixels (n a multiple of 8) along a row: the shared
// weight w = 2^(s + k |c(q) - c(p)|^2) (Tomasi & Manduchi 1998) is added to p's sums with q's
// validity and to q's sums with p's validity. P / Q select the sides.
template <bool P, bool Q>
[[gnu::always_inline]] inline void pairRun(const Quad& p, const Quad& q, const SumQuad& sp,
                                           const SumQuad& sq, int n, float k, float s) {
    for (int i = 0; i < n; i += 8) {
        VecF pr, pg, pb, pv, qr, qg, qb, qv;
        loadVec(pr, p.c[0] + i);
        loadVec(pg, p.c[1] + i);
        loadVec(pb, p.c[2] + i);
        loadVec(pv, p.c[3] + i);
        loadVec(qr, q.c[0] + i);
        loadVec(qg, q.c[1] + i);
        loadVec(qb, q.c[2] + i);
        loadVec(qv, q.c[3] + i);
        const VecF dr = qr - pr, dg = qg - pg, db = qb - pb;
        VecF w = (dr * dr + dg * dg + db * db) * k + s;
        exp2InPlace(w);
        if constexpr (P) {
            const VecF wp = w * qv;
            VecF ar, ag, ab, ad;
            loadVec(ar, sp.a[0] + i);
            loadVec(ag, sp.a[1] + i);
            loadVec(ab, sp.a[2] + i);
            loadVec(ad, sp.a[3] + i);
            storeVec(sp.a[0] + i, ar + wp * qr);
            storeVec(sp.a[1] + i, ag + wp * qg);
            storeVec(sp.a[2] + i, ab + wp * qb);
            storeVec(sp.a[3] + i, ad + wp);
        }
        if constexpr (Q) {
            const VecF wq = w * pv;
            VecF ar, ag, ab, ad;
            loadVec(ar, sq.a[0] + i);
            loadVec(ag, sq.a[1] + i);
            loadVec(ab, sq.a[2] + i);
            loadVec(ad, sq.a[3] + i);
            storeVec(sq.a[0] + i, ar + wq * pr);
            storeVec(sq.a[1] + i, ag + wq * pg);
            storeVec(sq.a[2] + i, ab + wq * pb);
            storeVec(sq.a[3] + i, ad + wq);
        }
    }
}

Quad planesAt(const PlanarPlanes& planes, int x, int y) {
    const std::size_t i = planes.index(x, y);
    return {{planes.planes[0].data() + i, planes.planes[1].data() + i, planes.planes[2].data() + i,
             planes.valid.data() + i}};
}

SumQuad sumsAt(SumRing& ring, int x, int y) {
    return {{ring.at(0, y, x), ring.at(1, y, x), ring.at(2, y, x), ring.at(3, y, x)}};
}

// All lower-half pairs of p-row y for the p columns [xa, xa + n) of band rows [b0, b1).
GLINT_SIMD_CLONES_V4
void lowerPairsTile(const ExactContext& ctx, SumRing& ring, int y, int b0, int b1, int xa, int n) {
    const bool pSide = y >= b0;
    const Quad p = planesAt(*ctx.planes, xa, y);
    const SumQuad sp = sumsAt(ring, xa, y);
    for (const Tap& t : ctx.lower) {
        const int qy = y + t.dy;
        const bool qSide = qy >= b0 && qy < b1;
        // Rows below the image are missing: zero weight for p.
        if (!qSide && (!pSide || qy >= ctx.imageHeight)) continue;
        const Quad q = planesAt(*ctx.planes, xa + t.dx, qy);
        if (pSide && qSide)
            pairRun<true, true>(p, q, sp, sumsAt(ring, xa + t.dx, qy), n, ctx.k, t.s);
        else if (pSide)
            pairRun<true, false>(p, q, sp, sp, n, ctx.k, t.s);
        else
            pairRun<false, true>(p, q, sp, sumsAt(ring, xa + t.dx, qy), n, ctx.k, t.s);
    }
}

// The centre row (dy = 0) of band row y, one-sided, for the roi's columns, added to the sums.
GLINT_SIMD_CLONES_V4
void centreRowPass(const ExactContext& ctx, SumRing& ring, int y) {
    for (int x = ctx.roi.x0; x < ctx.roi.x1; x += 8) {
        const Quad p = planesAt(*ctx.planes, x, y);
        VecF pr, pg, pb;
        loadVec(pr, p.c[0]);
        loadVec(pg, p.c[1]);
        loadVec(pb, p.c[2]);
        VecF nr{}, ng{}, nb{}, den{};
        for (const Tap& t : ctx.centre) {
            VecF qr, qg, qb, qv;
            loadVec(qr, p.c[0] + t.dx);
            loadVec(qg, p.c[1] + t.dx);
            loadVec(qb, p.c[2] + t.dx);
            loadVec(qv, p.c[3] + t.dx);
            const VecF dr = qr - pr, dg = qg - pg, db = qb - pb;
            addWeightedSamples((dr * dr + dg * dg + db * db) * ctx.k + t.s, qr, qg, qb, qv, nr, ng,
                               nb, den);
        }
        const SumQuad s = sumsAt(ring, x, y);
        const VecF* add[4] = {&nr, &ng, &nb, &den};
        for (int c = 0; c < 4; ++c) {
            VecF a;
            loadVec(a, s.a[c]);
            storeVec(s.a[c], a + *add[c]);
        }
    }
}

// Normalises the finished row y of the sums into `out` (the roi row) and clears it for reuse.
void finishRow(const ExactContext& ctx, SumRing& ring, int y, float* out) {
    const SumQuad s = sumsAt(ring, ctx.roi.x0, y);
    for (int i = 0; i < ctx.roi.width(); ++i) {
        const float den = s.a[3][i];
        const bool ok = den > 0.0f;
        for (int c = 0; c < 3; ++c) out[3 * i + c] = ok ? s.a[c][i] / den : 0.0f;
    }
    for (int c = 0; c < 4; ++c) std::fill_n(ring.at(c, y, ring.x0), ring.stride, 0.0f);
}

// True when every pixel of rows [y0, y1) in the roi's columns is finite (valid).
bool bandIsComplete(const ExactContext& ctx, int y0, int y1) {
    for (int y = y0; y < y1; ++y) {
        const float* v = ctx.planes->valid.data() + ctx.planes->index(ctx.roi.x0, y);
        for (int i = 0; i < ctx.roi.width(); ++i)
            if (v[i] == 0.0f) return false;
    }
    return true;
}

// Rows [b0, b1) of the roi by symmetric pairs.
void exactBand(const ExactContext& ctx, int b0, int b1, Image& out) {
    const int r = ctx.radius;
    SumRing ring;
    ring.rows = r + 1;
    ring.stride = ctx.planes->stride;
    ring.x0 = ctx.planes->rect.x0;
    ring.data.assign(std::size_t(4) * std::size_t(ring.rows) * std::size_t(ring.stride), 0.0f);
    for (int y = std::max(b0 - r, 0); y < b1; ++y) {
        for (int xa = ctx.px0; xa < ctx.px1; xa += kTileColumns) {
            const int n = (std::min(kTileColumns, ctx.px1 - xa) + 7) / 8 * 8;
            lowerPairsTile(ctx, ring, y, b0, b1, xa, n);
        }
        if (y < b0) continue;
        centreRowPass(ctx, ring, y);
        finishRow(ctx, ring, y, out.row(y - ctx.roi.y0));
    }
}

}  // namespace

Image bilateralExact(const Image& color, const Rect& roi, int radius, double sigmaS, double sigmaR,
                     WorkContext& work) {
    GLINT_CHECK(color.channels() == 3, "the bilateral filters need 3 colour channels");
    GLINT_CHECK(!roi.empty() && intersect(roi, color.bounds()) == roi);
    GLINT_CHECK(radius >= 0);
    GLINT_CHECK(sigmaS > 0.0 && sigmaR > 0.0 && std::isfinite(sigmaS) && std::isfinite(sigmaR));
    const int r = radius;
    // Planes: q reaches radius beyond the p columns, which reach radius beyond the roi; the
    // 8-wide tail of the last p group stays inside the planes' padding.
    const PlanarPlanes planes =
        makePlanar(color, Rect{roi.x0 - 2 * r, roi.x1 + 2 * r, roi.y0 - r, roi.y1 + r}, 3, work);
    ExactContext ctx;
    ctx.planes = &planes;
    ctx.roi = roi;
    ctx.radius = r;
    ctx.imageHeight = color.height();
    ctx.px0 = std::max(roi.x0 - r, 0);
    ctx.px1 = std::min(roi.x1 + r, color.width());
    ctx.k = rangeExponentScale(sigmaR);
    for (int dy = 0; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const float s = spatialExponent(dx, dy, sigmaS);
            if (s < -127.0f) continue;  // weight exactly 0
            (dy == 0 ? ctx.centre : ctx.lower).push_back({dx, dy, s});
        }
    Image out(roi.width(), roi.height(), 3);
    const int bandRows = std::max(kBandRows, 4 * r);
    const int firstBand = roi.y0 / bandRows, lastBand = (roi.y1 - 1) / bandRows;
    // A band of rows is the unit of work (and of cancellation).
    work.parallelFor(
        firstBand, lastBand + 1,
        [&](int band) {
            const int b0 = std::max(band * bandRows, roi.y0);
            const int b1 = std::min((band + 1) * bandRows, roi.y1);
            if (bandIsComplete(ctx, b0, b1))
                exactBand(ctx, b0, b1, out);
            else
                bilateralWindowRows(planes, roi, b0, b1, r, sigmaS, sigmaR, out);
        },
        bandRows);
    return out;
}

}  // namespace glint::denoise::detail
