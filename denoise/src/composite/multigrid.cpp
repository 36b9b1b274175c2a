#include "composite/multigrid.h"

#include "filters/simd.h"

namespace glint::denoise::multigrid {

namespace {

constexpr int kSmoothingSweeps = 2;  // red-black sweeps before and after the coarse correction
constexpr int kCoarsestSweeps = 40;  // symmetric sweeps on the coarsest grid
constexpr int kCoarsestSide = 4;     // stop coarsening at this shorter side …
constexpr int kCoarsestCells = 256;  // … or at this many cells

// One Gauss–Seidel half-sweep over the cells of one row's colour (x ≡ first mod 2): each
// becomes (r + Σ neighbours) / diag. Neighbours are of the other colour, so the order within the
// half-sweep does not matter: 8 cells at a time are computed and only this colour's lanes
// change. The left and right neighbours come from registers (the previous and next vectors),
// not from reloading what was just stored (a store-forwarding stall).
GLINT_SIMD_CLONES void smoothRow(float* e, const float* up, const float* down, const float* r,
                                 const float* inv, int w, int first) {
    using detail::VecF;
    using detail::VecI;
    const VecI lane = {0, 1, 2, 3, 4, 5, 6, 7};
    const VecI mine = (lane & 1) == first;
    int x = 0;
    if (w >= 8) {
        VecF prev = VecF{} + e[-1], c;
        detail::loadVec(c, e);
        for (; x + 8 <= w; x += 8) {
            VecF next, u, d, rhs, scale;
            if (x + 16 <= w)
                detail::loadVec(next, e + x + 8);
            else
                next = VecF{} + e[x + 8];  // only lane 0 is used
            detail::loadVec(u, up + x);
            detail::loadVec(d, down + x);
            detail::loadVec(rhs, r + x);
            detail::loadVec(scale, inv + x);
            const VecF left = __builtin_shufflevector(prev, c, 7, 8, 9, 10, 11, 12, 13, 14);
            const VecF right = __builtin_shufflevector(c, next, 1, 2, 3, 4, 5, 6, 7, 8);
            const VecF updated = ((rhs + u) + (d + left) + right) * scale;
            detail::storeVec(e + x, mine ? updated : c);
            // The old values: the lanes a neighbour is read from are of the other colour,
            // unchanged, and the loop carries no dependency on the arithmetic.
            prev = c;
            c = next;
        }
    }
    for (x += (x + first) & 1; x < w; x += 2)
        e[x] = (r[x] + e[x - 1] + e[x + 1] + up[x] + down[x]) * inv[x];
}

void smooth(Level& L, int parity) {
    forRows(L.w, L.h, [&](int y) {
        float* e = L.e.data() + L.at(0, y);
        smoothRow(e, e - L.stride, e + L.stride, L.r.data() + L.at(0, y), L.inv.data() + L.at(0, y),
                  L.w, (y + parity) & 1);
    });
}

// The first red half-sweep from e = 0 over a row: red cells (x ≡ first mod 2) r / diag, black
// cells 0.
GLINT_SIMD_CLONES void smoothRowFromZero(float* e, const float* r, const float* inv, int w,
                                         int first) {
    using detail::VecF;
    using detail::VecI;
    const VecI lane = {0, 1, 2, 3, 4, 5, 6, 7};
    const VecI mine = (lane & 1) == first;
    int x = 0;
    for (; x + 8 <= w; x += 8) {
        VecF rhs, scale;
        detail::loadVec(rhs, r + x);
        detail::loadVec(scale, inv + x);
        detail::storeVec(e + x, mine ? rhs * scale : VecF{});
    }
    for (; x < w; ++x) e[x] = ((x + first) & 1) == 0 ? r[x] * inv[x] : 0.0f;
}

void smoothFromZero(Level& L) {
    forRows(L.w, L.h, [&](int y) {
        smoothRowFromZero(L.e.data() + L.at(0, y), L.r.data() + L.at(0, y),
                          L.inv.data() + L.at(0, y), L.w, y & 1);
    });
}

// res = r − A e over a row.
GLINT_SIMD_CLONES void residualRow(float* res, const float* e, const float* up, const float* down,
                                   const float* r, const float* diag, int w) {
    using detail::VecF;
    int x = 0;
    for (; x + 8 <= w; x += 8) {
        VecF c, left, right, u, d, rhs, dg;
        detail::loadVec(c, e + x);
        detail::loadVec(left, e + x - 1);
        detail::loadVec(right, e + x + 1);
        detail::loadVec(u, up + x);
        detail::loadVec(d, down + x);
        detail::loadVec(rhs, r + x);
        detail::loadVec(dg, diag + x);
        detail::storeVec(res + x, rhs + left + right + u + d - dg * c);
    }
    for (; x < w; ++x) res[x] = r[x] + e[x - 1] + e[x + 1] + up[x] + down[x] - diag[x] * e[x];
}

// C.r = the sum of the residuals r − A e of each free coarse cell's children (0 on fixed coarse
// cells, whose children may include fixed cells).
void restrictResidual(const Level& L, Level& C) {
    forRows(C.w, C.h, [&](int Y) {
        std::vector<float> res(std::size_t(L.w) + 1, 0.0f);
        float* cr = C.r.data() + C.at(0, Y);
        const float* cdiag = C.diag.data() + C.at(0, Y);
        std::fill(cr, cr + C.w, 0.0f);
        for (int y = 2 * Y; y < std::min(2 * Y + 2, L.h); ++y) {
            const float* e = L.e.data() + L.at(0, y);
            residualRow(res.data(), e, e - L.stride, e + L.stride, L.r.data() + L.at(0, y),
                        L.diag.data() + L.at(0, y), L.w);
            for (int X = 0; X < C.w; ++X)
                cr[X] += res[std::size_t(2 * X)] + res[std::size_t(2 * X + 1)];
        }
        for (int X = 0; X < C.w; ++X)
            if (cdiag[X] == 0.0f) cr[X] = 0.0f;
    });
}

// e += the coarse correction over a row, injected into the free children.
GLINT_SIMD_CLONES void prolongateRow(float* e, const float* diag, const float* ce, int w) {
    using detail::VecF;
    int x = 0;
    for (; x + 8 <= w; x += 8) {
        VecF c{}, fine, dg;
        std::memcpy(&c, ce + x / 2, 4 * sizeof(float));
        detail::loadVec(fine, e + x);
        detail::loadVec(dg, diag + x);
        const VecF twice = __builtin_shufflevector(c, c, 0, 0, 1, 1, 2, 2, 3, 3);
        detail::storeVec(e + x, dg > 0.0f ? fine + twice : fine);
    }
    for (; x < w; ++x)
        if (diag[x] > 0.0f) e[x] += ce[x / 2];
}

void prolongate(const Level& C, Level& L) {
    forRows(L.w, L.h, [&](int y) {
        prolongateRow(L.e.data() + L.at(0, y), L.diag.data() + L.at(0, y),
                      C.e.data() + C.at(0, y / 2), L.w);
    });
}

}  // namespace

std::vector<Level> buildHierarchy(int w, int h, const float* fixed) {
    std::vector<Level> levels;
    levels.emplace_back(w, h);
    levels[0].initGhosts();
    forRows(w, h, [&](int y) {
        const float* f = fixed + std::size_t(y) * std::size_t(w);
        levels[0].initRow(y, [&](int x) { return !(f[x] > 0.0f); });
    });
    while (std::min(levels.back().w, levels.back().h) > kCoarsestSide &&
           levels.back().w * levels.back().h > kCoarsestCells) {
        const Level& F = levels.back();
        Level C((F.w + 1) / 2, (F.h + 1) / 2);
        C.initGhosts();
        forRows(C.w, C.h, [&](int Y) {
            C.initRow(Y, [&](int X) {
                bool allFree = true;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int x = 2 * X + dx, y = 2 * Y + dy;
                        if (x < F.w && y < F.h) allFree = allFree && F.diag[F.at(x, y)] > 0.0f;
                    }
                return allFree;
            });
        });
        levels.push_back(std::move(C));
    }
    return levels;
}

void vCycle(std::vector<Level>& levels, std::size_t l) {
    Level& L = levels[l];
    if (l + 1 == levels.size()) {
        // Symmetric sweeps (red, black, black, red) from 0; a repeated half-sweep changes
        // nothing, so they chain as red, (black, red) × kCoarsestSweeps: a palindrome.
        smoothFromZero(L);
        for (int it = 0; it < kCoarsestSweeps; ++it) {
            smooth(L, 1);
            smooth(L, 0);
        }
        return;
    }
    // Pre-smoothing red → black.
    smoothFromZero(L);
    smooth(L, 1);
    for (int s = 1; s < kSmoothingSweeps; ++s) {
        smooth(L, 0);
        smooth(L, 1);
    }
    // Coarse-grid correction.
    restrictResidual(L, levels[l + 1]);
    vCycle(levels, l + 1);
    prolongate(levels[l + 1], L);
    // Post-smoothing black → red (the adjoint of the pre-smoothing).
    for (int s = 0; s < kSmoothingSweeps; ++s) {
        smooth(L, 1);
        smooth(L, 0);
    }
}

}  // namespace glint::denoise::multigrid
