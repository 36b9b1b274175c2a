// Inner loops of the bilateral filters: weights as Tomasi & Manduchi 1998; the sampled variant
// evaluates the same estimator on a per-pixel subset of the window (Banterle et al. 2012, Sec. 3).
#include "filters/bilateral_kernel.h"

#include <algorithm>
#include <cmath>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

// A pattern ready for the inner loop: linear offsets into the planes and spatial weights,
// padded with (0, weight 0) entries to a multiple of 8.
struct PreparedPattern {
    std::vector<std::ptrdiff_t> delta;
    std::vector<std::int32_t> delta32;  // the same as 32-bit gather indices
    std::vector<float> spatial;
    int count = 0;  // padded length
};

PreparedPattern prepare(const BilateralPattern& pattern, int radius, double sigmaS, int stride,
                        bool pad) {
    PreparedPattern out;
    // Row-major order: neighbouring samples share cache lines.
    std::vector<Offset> sorted = pattern.offsets;
    std::sort(sorted.begin(), sorted.end(), [](const Offset& a, const Offset& b) {
        return a.dy != b.dy ? a.dy < b.dy : a.dx < b.dx;
    });
    for (const Offset& o : sorted) {
        GLINT_CHECK(std::abs(o.dx) <= radius && std::abs(o.dy) <= radius);
        // Spatial Gaussian on scaled offsets: sigmaS = 1e-6 underflows to 0, never overflows.
        const double tx = o.dx / sigmaS, ty = o.dy / sigmaS;
        const float w = float(std::exp(-0.5 * (tx * tx + ty * ty)));
        if (w == 0.0f) continue;  // contributes nothing
        out.delta.push_back(std::ptrdiff_t(o.dy) * stride + o.dx);
        out.spatial.push_back(w);
    }
    while (pad && out.delta.size() % 8 != 0) {
        out.delta.push_back(0);
        out.spatial.push_back(0.0f);
    }
    out.count = int(out.delta.size());
    for (std::ptrdiff_t d : out.delta) out.delta32.push_back(std::int32_t(d));
    return out;
}

// Writes num/den (0 where den is 0) for `lanes` pixels.
void writeNormalised(const VecF& nr, const VecF& ng, const VecF& nb, const VecF& den, int lanes,
                     float* out) {
    for (int l = 0; l < lanes; ++l) {
        const bool ok = den[l] > 0.0f;
        out[3 * l + 0] = ok ? nr[l] / den[l] : 0.0f;
        out[3 * l + 1] = ok ? ng[l] / den[l] : 0.0f;
        out[3 * l + 2] = ok ? nb[l] / den[l] : 0.0f;
    }
}

// One output row of the shared-pattern filter, 8 output pixels at a time.
GLINT_SIMD_CLONES
void windowedRow(const PlanarPlanes& planes, int y, int x0, int x1, const PreparedPattern& pat,
                 float rangeScale, float* out) {
    const float* pr = planes.planes[0].data();
    const float* pg = planes.planes[1].data();
    const float* pb = planes.planes[2].data();
    const float* pv = planes.valid.data();
    for (int x = x0; x < x1; x += 8) {
        const std::size_t ci = planes.index(x, y);
        VecF cr, cg, cb, cv;
        loadVec(cr, pr + ci);
        loadVec(cg, pg + ci);
        loadVec(cb, pb + ci);
        loadVec(cv, pv + ci);
        const VecI centreMissing = cv == 0.0f;
        VecF nr{}, ng{}, nb{}, den{};
        for (int j = 0; j < pat.count; ++j) {
            const std::size_t qi = std::size_t(std::ptrdiff_t(ci) + pat.delta[std::size_t(j)]);
            VecF qr, qg, qb, qv;
            loadVec(qr, pr + qi);
            loadVec(qg, pg + qi);
            loadVec(qb, pb + qi);
            loadVec(qv, pv + qi);
            // Range weight on differences scaled by 1/(sqrt(2) sigmaR) before squaring.
            const VecF dr = (qr - cr) * rangeScale, dg = (qg - cg) * rangeScale,
                       db = (qb - cb) * rangeScale;
            VecF w = -(dr * dr + dg * dg + db * db);
            expNegInPlace(w);
            w = centreMissing ? (VecF{} + 1.0f) : w;
            w *= qv * pat.spatial[std::size_t(j)];
            nr += w * qr;
            ng += w * qg;
            nb += w * qb;
            den += w;
        }
        writeNormalised(nr, ng, nb, den, std::min(8, x1 - x), out + std::size_t(x - x0) * 3);
    }
}

// Range and spatial weights of 8 samples against a centre, accumulated (Tomasi & Manduchi 1998):
// w = spatial * valid * exp(-|(q - c) / (sqrt(2) sigmaR)|^2); a missing centre drops the range
// term.
[[gnu::always_inline]] inline void accumulateSamples(const VecF& qr, const VecF& qg, const VecF& qb,
                                                     const VecF& qv, const VecF& ws, const VecF& cr,
                                                     const VecF& cg, const VecF& cb,
                                                     bool centreMissing, float rangeScale, VecF& nr,
                                                     VecF& ng, VecF& nb, VecF& den) {
    const VecF dr = (qr - cr) * rangeScale, dg = (qg - cg) * rangeScale,
               db = (qb - cb) * rangeScale;
    VecF w = -(dr * dr + dg * dg + db * db);
    expNegInPlace(w);
    if (centreMissing) w = VecF{} + 1.0f;
    w *= qv * ws;
    nr += w * qr;
    ng += w * qg;
    nb += w * qb;
    den += w;
}

// Writes the lane sums num/den (0 where den is 0) of one pixel.
[[gnu::always_inline]] inline void writePixel(const VecF& nr, const VecF& ng, const VecF& nb,
                                              const VecF& den, float* o) {
    float sr = 0.0f, sg = 0.0f, sb = 0.0f, sd = 0.0f;
    for (int l = 0; l < 8; ++l) {
        sr += nr[l];
        sg += ng[l];
        sb += nb[l];
        sd += den[l];
    }
    const bool ok = sd > 0.0f;
    o[0] = ok ? sr / sd : 0.0f;
    o[1] = ok ? sg / sd : 0.0f;
    o[2] = ok ? sb / sd : 0.0f;
}

// Arguments of one row of the per-pixel-pattern filter.
struct SampledRow {
    const PlanarPlanes* planes;
    int y, x0, x1;
    const std::vector<PreparedPattern>* pats;
    std::uint64_t seed;
    float rangeScale;
    float* out;
    const float* interleaved;  // (r, g, b, valid) per pixel, same indexing as the planes
};

// One output row of the per-pixel-pattern filter, 8 samples of one pixel at a time; portable
// version (lane-by-lane loads).
void sampledRowPortable(const SampledRow& a) {
    const PlanarPlanes& planes = *a.planes;
    const float* pr = planes.planes[0].data();
    const float* pg = planes.planes[1].data();
    const float* pb = planes.planes[2].data();
    const float* pv = planes.valid.data();
    const auto count = std::uint32_t(a.pats->size());
    for (int x = a.x0; x < a.x1; ++x) {
        const std::size_t ci = planes.index(x, a.y);
        const VecF cr = VecF{} + pr[ci], cg = VecF{} + pg[ci], cb = VecF{} + pb[ci];
        const bool centreMissing = pv[ci] == 0.0f;
        // Banterle et al. 2012: each pixel uses one of the precomputed patterns at random.
        const PreparedPattern& pat = (*a.pats)[patternIndex(x, a.y, a.seed, count)];
        VecF nr{}, ng{}, nb{}, den{};
        for (int j = 0; j < pat.count; j += 8) {
            VecF qr, qg, qb, qv, ws;
            for (int l = 0; l < 8; ++l) {
                const std::size_t qi =
                    std::size_t(std::ptrdiff_t(ci) + pat.delta[std::size_t(j + l)]);
                qr[l] = pr[qi];
                qg[l] = pg[qi];
                qb[l] = pb[qi];
                qv[l] = pv[qi];
            }
            loadVec(ws, pat.spatial.data() + j);
            accumulateSamples(qr, qg, qb, qv, ws, cr, cg, cb, centreMissing, a.rangeScale, nr, ng,
                              nb, den);
        }
        writePixel(nr, ng, nb, den, a.out + std::size_t(x - a.x0) * 3);
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same on the interleaved (r, g, b, valid) copy with AVX2: 8 samples are 8 16-byte loads
// transposed into r, g, b, valid vectors (one cache line per sample instead of four).
__attribute__((target("avx2,fma"))) void sampledRowAvx2(const SampledRow& a) {
    const PlanarPlanes& planes = *a.planes;
    const float* rgbv = a.interleaved;
    const auto count = std::uint32_t(a.pats->size());
    for (int x = a.x0; x < a.x1; ++x) {
        const std::size_t ci = planes.index(x, a.y);
        const float* centre = rgbv + 4 * ci;
        const VecF cr = VecF{} + centre[0], cg = VecF{} + centre[1], cb = VecF{} + centre[2];
        const bool centreMissing = centre[3] == 0.0f;
        // Banterle et al. 2012: each pixel uses one of the precomputed patterns at random.
        const PreparedPattern& pat = (*a.pats)[patternIndex(x, a.y, a.seed, count)];
        const std::int32_t* d = pat.delta32.data();
        VecF nr{}, ng{}, nb{}, den{};
        for (int j = 0; j < pat.count; j += 8, d += 8) {
            // Rows hold two samples each: t0 = [s0 | s4], t1 = [s1 | s5], ...
            const __m256 t0 = _mm256_insertf128_ps(
                _mm256_castps128_ps256(_mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[0]))),
                _mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[4])), 1);
            const __m256 t1 = _mm256_insertf128_ps(
                _mm256_castps128_ps256(_mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[1]))),
                _mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[5])), 1);
            const __m256 t2 = _mm256_insertf128_ps(
                _mm256_castps128_ps256(_mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[2]))),
                _mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[6])), 1);
            const __m256 t3 = _mm256_insertf128_ps(
                _mm256_castps128_ps256(_mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[3]))),
                _mm_loadu_ps(centre + 4 * std::ptrdiff_t(d[7])), 1);
            // 4x4 transpose in each 128-bit half.
            const __m256 u0 = _mm256_unpacklo_ps(t0, t1), u1 = _mm256_unpackhi_ps(t0, t1);
            const __m256 u2 = _mm256_unpacklo_ps(t2, t3), u3 = _mm256_unpackhi_ps(t2, t3);
            const VecF qr = VecF(_mm256_shuffle_ps(u0, u2, 0x44));
            const VecF qg = VecF(_mm256_shuffle_ps(u0, u2, 0xEE));
            const VecF qb = VecF(_mm256_shuffle_ps(u1, u3, 0x44));
            const VecF qv = VecF(_mm256_shuffle_ps(u1, u3, 0xEE));
            VecF ws;
            loadVec(ws, pat.spatial.data() + j);
            accumulateSamples(qr, qg, qb, qv, ws, cr, cg, cb, centreMissing, a.rangeScale, nr, ng,
                              nb, den);
        }
        writePixel(nr, ng, nb, den, a.out + std::size_t(x - a.x0) * 3);
    }
}
#endif

void sampledRow(const SampledRow& a) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return sampledRowAvx2(a);
#endif
    sampledRowPortable(a);
}

void checkInputs(const Image& color, const Rect& roi, int radius, double sigmaS, double sigmaR) {
    GLINT_CHECK(color.channels() == 3, "the bilateral filters need 3 colour channels");
    GLINT_CHECK(!roi.empty() && intersect(roi, color.bounds()) == roi);
    GLINT_CHECK(radius >= 0);
    GLINT_CHECK(sigmaS > 0.0 && sigmaR > 0.0 && std::isfinite(sigmaS) && std::isfinite(sigmaR));
}

// Planes over roi plus the window radius (outside the image: missing).
PlanarPlanes planesFor(const Image& color, const Rect& roi, int radius) {
    return makePlanar(color,
                      Rect{roi.x0 - radius, roi.x1 + radius, roi.y0 - radius, roi.y1 + radius}, 3);
}

float rangeScaleOf(double sigmaR) {
    return float(1.0 / (std::sqrt(2.0) * sigmaR));
}

}  // namespace

std::uint32_t patternIndex(int x, int y, std::uint64_t seed, std::uint32_t count) {
    // SplitMix64 finaliser of (seed, x, y).
    std::uint64_t z =
        seed * 0x9E3779B97F4A7C15ull + (std::uint64_t(std::uint32_t(y)) << 32) + std::uint32_t(x);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return std::uint32_t(z % count);
}

Image bilateralWindowed(const Image& color, const Rect& roi, int radius, double sigmaS,
                        double sigmaR, const BilateralPattern& pattern) {
    checkInputs(color, roi, radius, sigmaS, sigmaR);
    const PlanarPlanes planes = planesFor(color, roi, radius);
    const PreparedPattern pat = prepare(pattern, radius, sigmaS, planes.stride, false);
    const float rangeScale = rangeScaleOf(sigmaR);
    Image out(roi.width(), roi.height(), 3);
    parallelRows(roi.y0, roi.y1, [&](int y) {
        windowedRow(planes, y, roi.x0, roi.x1, pat, rangeScale, out.row(y - roi.y0));
    });
    return out;
}

Image bilateralSampled(const Image& color, const Rect& roi, int radius, double sigmaS,
                       double sigmaR, const std::vector<BilateralPattern>& patterns,
                       std::uint64_t seed) {
    checkInputs(color, roi, radius, sigmaS, sigmaR);
    GLINT_CHECK(!patterns.empty());
    const PlanarPlanes planes = planesFor(color, roi, radius);
    std::vector<PreparedPattern> pats;
    pats.reserve(patterns.size());
    for (const BilateralPattern& p : patterns)
        pats.push_back(prepare(p, radius, sigmaS, planes.stride, true));
    const float rangeScale = rangeScaleOf(sigmaR);
    // Interleaved (r, g, b, valid) copy for the AVX2 path.
    std::vector<float> interleaved(planes.valid.size() * 4);
    parallelRows(0, planes.rect.height(), [&](int row) {
        for (std::size_t i = std::size_t(row) * std::size_t(planes.stride),
                         end = i + std::size_t(planes.stride);
             i < end; ++i) {
            interleaved[4 * i + 0] = planes.planes[0][i];
            interleaved[4 * i + 1] = planes.planes[1][i];
            interleaved[4 * i + 2] = planes.planes[2][i];
            interleaved[4 * i + 3] = planes.valid[i];
        }
    });
    Image out(roi.width(), roi.height(), 3);
    parallelRows(roi.y0, roi.y1, [&](int y) {
        sampledRow({&planes, y, roi.x0, roi.x1, &pats, seed, rangeScale, out.row(y - roi.y0),
                    interleaved.data()});
    });
    return out;
}

}  // namespace glint::denoise::detail
