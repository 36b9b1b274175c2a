// Inner loops of the bilateral filters: weights as Tomasi & Manduchi 1998; the sampled variant
// evaluates the same estimator on a per-pixel subset of the window (Banterle et al. 2012, Sec. 3).
#include "filters/bilateral_kernel.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>

#include "filters/filter_util.h"
#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

// Eight samples of a padded pattern in one cache line: byte offsets into the interleaved
// (r, g, b, valid) copy and spatial exponents (the inner loop of bilateral-mc).
struct alignas(64) SampleGroup {
    std::int32_t offset[8];
    float s[8];
};

// A pattern ready for the inner loops: linear pixel offsets into a layout of the given stride
// and base-2 spatial exponents, in row-major order; when padded, extended with (0, exponent
// -1e30 = weight 0) entries to a multiple of 8 and also stored as SampleGroups.
struct PreparedPattern {
    std::vector<std::ptrdiff_t> delta;
    std::vector<float> spatial;       // spatialExponent of each offset
    std::vector<SampleGroup> groups;  // filled when padded
    int count = 0;                    // (padded) length
};

constexpr float kZeroWeightExponent = -1e30f;

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
        const float s = spatialExponent(o.dx, o.dy, sigmaS);
        if (s < -127.0f) continue;  // weight exactly 0: contributes nothing
        out.delta.push_back(std::ptrdiff_t(o.dy) * stride + o.dx);
        out.spatial.push_back(s);
    }
    while (pad && out.delta.size() % 8 != 0) {
        out.delta.push_back(0);
        out.spatial.push_back(kZeroWeightExponent);
    }
    out.count = int(out.delta.size());
    for (std::size_t g = 0; pad && g < out.delta.size(); g += 8) {
        SampleGroup group;
        for (std::size_t l = 0; l < 8; ++l) {
            group.offset[l] = std::int32_t(out.delta[g + l] * std::ptrdiff_t(4 * sizeof(float)));
            group.s[l] = out.spatial[g + l];
        }
        out.groups.push_back(group);
    }
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

// One output row of the one-sided full-window filter, 8 output pixels at a time (the fallback of
// the exact filter for bands with missing pixels).
GLINT_SIMD_CLONES_V4
void windowedRow(const PlanarPlanes& planes, int y, int x0, int x1, const PreparedPattern& pat,
                 float k, float* out) {
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
            // Tomasi & Manduchi 1998 weight in base 2; a missing centre drops the range term.
            const VecF dr = qr - cr, dg = qg - cg, db = qb - cb;
            const VecF s = VecF{} + pat.spatial[std::size_t(j)];
            const VecF w = (dr * dr + dg * dg + db * db) * k + s;
            addWeightedSamples(centreMissing ? s : w, qr, qg, qb, qv, nr, ng, nb, den);
        }
        writeNormalised(nr, ng, nb, den, std::min(8, x1 - x), out + std::size_t(x - x0) * 3);
    }
}

// Weights of 8 samples against a centre, accumulated (Tomasi & Manduchi 1998):
// w = valid * 2^(s + k |q - c|^2); a missing centre drops the range term.
template <bool CentreMissing>
[[gnu::always_inline]] inline void accumulateSamples(const VecF& qr, const VecF& qg, const VecF& qb,
                                                     const VecF& qv, const VecF& s, const VecF& cr,
                                                     const VecF& cg, const VecF& cb, float k,
                                                     VecF& nr, VecF& ng, VecF& nb, VecF& den) {
    VecF w = s;
    if constexpr (!CentreMissing) {
        const VecF dr = qr - cr, dg = qg - cg, db = qb - cb;
        w = (dr * dr + dg * dg + db * db) * k + s;
    }
    addWeightedSamples(w, qr, qg, qb, qv, nr, ng, nb, den);
}

// Interleaved (r, g, b, valid) copy of the colour over a rectangle that may reach outside the
// image; missing pixels (outside, or non-finite) are (0, 0, 0, 0). One 16-byte load per sample.
struct InterleavedColor {
    Rect rect;
    int stride = 0;  // pixels per row
    std::unique_ptr<float[]> data;

    /// The (r, g, b, valid) of image pixel (x, y), which must lie in rect.
    float* at(int x, int y) const {
        return data.get() +
               4 * (std::size_t(y - rect.y0) * std::size_t(stride) + std::size_t(x - rect.x0));
    }
};

// Builds the interleaved copy in one parallel pass (every value written once, no zero fill).
InterleavedColor makeInterleaved(const Image& color, const Rect& rect, WorkContext& work) {
    InterleavedColor c;
    c.rect = rect;
    c.stride = rect.width();
    c.data.reset(new float[4 * std::size_t(rect.width()) * std::size_t(rect.height())]);
    work.parallelFor(
        rect.y0, rect.y1,
        [&](int y) {
            float* dst = c.at(rect.x0, y);
            const bool rowInside = y >= 0 && y < color.height();
            for (int x = rect.x0; x < rect.x1; ++x, dst += 4) {
                const float* px = rowInside && x >= 0 && x < color.width()
                                      ? color.row(y) + 3 * std::size_t(x)
                                      : nullptr;
                const bool ok = px && isFinitePixel(px, 3);
                for (int ch = 0; ch < 3; ++ch) dst[ch] = ok ? px[ch] : 0.0f;
                dst[3] = ok ? 1.0f : 0.0f;
            }
        },
        0);
    return c;
}

// Arguments of one row of the per-pixel-pattern filter.
struct SampledRow {
    const InterleavedColor* color;
    int y, x0, x1;
    const std::vector<PreparedPattern>* pats;
    std::uint64_t seed;
    float k;
    float* out;
};

typedef float Vec4F __attribute__((vector_size(16)));

// Per-pixel state of the sampled kernel: the centre, the next group of its pattern, the sums.
struct PixelSums {
    const float* centre;  // (r, g, b, valid) in the interleaved copy
    const SampleGroup* group;
    VecF cr, cg, cb;
    VecF nr{}, ng{}, nb{}, den{};
};

// One group of 8 samples of pixel `p` on the interleaved (r, g, b, valid) copy: 8 16-byte loads
// (one cache line per sample instead of four) transposed into r, g, b, valid vectors with
// in-lane unpacks and shuffles.
template <bool CentreMissing>
[[gnu::always_inline]] inline void sampleGroup(PixelSums& p, float k) {
    const char* base = reinterpret_cast<const char*>(p.centre);
    const std::int32_t* d = p.group->offset;
    Vec4F s[8];
    for (int i = 0; i < 8; ++i) std::memcpy(&s[i], base + d[i], sizeof(Vec4F));
    // Rows hold two samples each: t0 = [s0 | s4], t1 = [s1 | s5], ...
    const VecF t0 = __builtin_shufflevector(s[0], s[4], 0, 1, 2, 3, 4, 5, 6, 7);
    const VecF t1 = __builtin_shufflevector(s[1], s[5], 0, 1, 2, 3, 4, 5, 6, 7);
    const VecF t2 = __builtin_shufflevector(s[2], s[6], 0, 1, 2, 3, 4, 5, 6, 7);
    const VecF t3 = __builtin_shufflevector(s[3], s[7], 0, 1, 2, 3, 4, 5, 6, 7);
    // 4x4 transpose in each 128-bit half (unpacklo/hi, then shuffle).
    const VecF u0 = __builtin_shufflevector(t0, t1, 0, 8, 1, 9, 4, 12, 5, 13);
    const VecF u1 = __builtin_shufflevector(t0, t1, 2, 10, 3, 11, 6, 14, 7, 15);
    const VecF u2 = __builtin_shufflevector(t2, t3, 0, 8, 1, 9, 4, 12, 5, 13);
    const VecF u3 = __builtin_shufflevector(t2, t3, 2, 10, 3, 11, 6, 14, 7, 15);
    const VecF qr = __builtin_shufflevector(u0, u2, 0, 1, 8, 9, 4, 5, 12, 13);
    const VecF qg = __builtin_shufflevector(u0, u2, 2, 3, 10, 11, 6, 7, 14, 15);
    const VecF qb = __builtin_shufflevector(u1, u3, 0, 1, 8, 9, 4, 5, 12, 13);
    const VecF qv = __builtin_shufflevector(u1, u3, 2, 3, 10, 11, 6, 7, 14, 15);
    VecF ws;
    loadVec(ws, p.group->s);
    accumulateSamples<CentreMissing>(qr, qg, qb, qv, ws, p.cr, p.cg, p.cb, k, p.nr, p.ng, p.nb,
                                     p.den);
    ++p.group;
}

// The remaining groups of one pixel.
[[gnu::always_inline]] inline void sampleRest(PixelSums& p, const SampleGroup* end, float k) {
    if (p.centre[3] == 0.0f)
        while (p.group != end) sampleGroup<true>(p, k);
    else
        while (p.group != end) sampleGroup<false>(p, k);
}

// h <- the pairwise lane sums of a and b in the order of the x86 hadd instruction.
[[gnu::always_inline]] inline void pairSums(const VecF& a, const VecF& b, VecF& h) {
    h = __builtin_shufflevector(a, b, 0, 2, 8, 10, 4, 6, 12, 14) +
        __builtin_shufflevector(a, b, 1, 3, 9, 11, 5, 7, 13, 15);
}

// Writes num/den of one pixel (0 where the weight sum is 0).
[[gnu::always_inline]] inline void writeSums(const PixelSums& p, float* o) {
    // Lane sums of the four accumulators at once: h = (r, g, b, weight) in each 128-bit half.
    VecF rg, bw, h;
    pairSums(p.nr, p.ng, rg);
    pairSums(p.nb, p.den, bw);
    pairSums(rg, bw, h);
    const float sums[4] = {h[0] + h[4], h[1] + h[5], h[2] + h[6], h[3] + h[7]};
    const bool ok = sums[3] > 0.0f;
    for (int c = 0; c < 3; ++c) o[c] = ok ? sums[c] / sums[3] : 0.0f;
}

// One output row of the per-pixel-pattern filter, two pixels at a time: their groups are
// interleaved so that two independent dependency chains (loads -> exp2 -> sums) overlap.
GLINT_SIMD_CLONES_V4
void sampledRow(const SampledRow& a) {
    const auto count = std::uint32_t(a.pats->size());
    auto start = [&](int x, const SampleGroup*& end) {
        const float* centre = a.color->at(x, a.y);
        // Banterle et al. 2012: each pixel uses one of the precomputed patterns at random.
        const PreparedPattern& pat = (*a.pats)[patternIndex(x, a.y, a.seed, count)];
        end = pat.groups.data() + pat.groups.size();
        return PixelSums{centre, pat.groups.data(), VecF{} + centre[0], VecF{} + centre[1],
                         VecF{} + centre[2]};
    };
    int x = a.x0;
    for (; x + 1 < a.x1; x += 2) {
        const SampleGroup *end0, *end1;
        PixelSums p0 = start(x, end0), p1 = start(x + 1, end1);
        if (p0.centre[3] != 0.0f && p1.centre[3] != 0.0f)
            while (p0.group != end0 && p1.group != end1) {
                sampleGroup<false>(p0, a.k);
                sampleGroup<false>(p1, a.k);
            }
        sampleRest(p0, end0, a.k);
        sampleRest(p1, end1, a.k);
        writeSums(p0, a.out + std::size_t(x - a.x0) * 3);
        writeSums(p1, a.out + std::size_t(x + 1 - a.x0) * 3);
    }
    if (x < a.x1) {
        const SampleGroup* end0;
        PixelSums p0 = start(x, end0);
        sampleRest(p0, end0, a.k);
        writeSums(p0, a.out + std::size_t(x - a.x0) * 3);
    }
}

void checkInputs(const Image& color, const Rect& roi, int radius, double sigmaS, double sigmaR) {
    GLINT_CHECK(color.channels() == 3, "the bilateral filters need 3 colour channels");
    GLINT_CHECK(!roi.empty() && intersect(roi, color.bounds()) == roi);
    GLINT_CHECK(radius >= 0);
    GLINT_CHECK(sigmaS > 0.0 && sigmaR > 0.0 && std::isfinite(sigmaS) && std::isfinite(sigmaR));
}

}  // namespace

float spatialExponent(int dx, int dy, double sigmaS) {
    const double tx = dx / sigmaS, ty = dy / sigmaS;
    return float(std::max(-0.5 * std::log2(std::exp(1.0)) * (tx * tx + ty * ty), -1e30));
}

float rangeExponentScale(double sigmaR) {
    const double inv = 1.0 / sigmaR;
    return float(-0.5 * std::log2(std::exp(1.0)) * inv * inv);
}

void bilateralWindowRows(const PlanarPlanes& planes, const Rect& roi, int y0, int y1, int radius,
                         double sigmaS, double sigmaR, Image& out) {
    BilateralPattern window;
    for (int dy = -radius; dy <= radius; ++dy)
        for (int dx = -radius; dx <= radius; ++dx) window.offsets.push_back({dx, dy});
    const PreparedPattern pat = prepare(window, radius, sigmaS, planes.stride, false);
    const float k = rangeExponentScale(sigmaR);
    for (int y = y0; y < y1; ++y)
        windowedRow(planes, y, roi.x0, roi.x1, pat, k, out.row(y - roi.y0));
}

Image bilateralSampled(const Image& color, const Rect& roi, int radius, double sigmaS,
                       double sigmaR, const std::vector<BilateralPattern>& patterns,
                       std::uint64_t seed, WorkContext& work) {
    checkInputs(color, roi, radius, sigmaS, sigmaR);
    GLINT_CHECK(!patterns.empty());
    const InterleavedColor interleaved = makeInterleaved(
        color, Rect{roi.x0 - radius, roi.x1 + radius, roi.y0 - radius, roi.y1 + radius}, work);
    std::vector<PreparedPattern> pats;
    pats.reserve(patterns.size());
    for (const BilateralPattern& p : patterns)
        pats.push_back(prepare(p, radius, sigmaS, interleaved.stride, true));
    const float k = rangeExponentScale(sigmaR);
    Image out(roi.width(), roi.height(), 3);
    work.parallelFor(roi.y0, roi.y1, [&](int y) {
        sampledRow({&interleaved, y, roi.x0, roi.x1, &pats, seed, k, out.row(y - roi.y0)});
    });
    return out;
}

}  // namespace glint::denoise::detail
