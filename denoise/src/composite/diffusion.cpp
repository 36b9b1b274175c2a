// Poisson-diffusion blending: the steady state of the heat equation with the painted pixels held
// fixed, i.e. the discrete Laplace equation (5-point stencil, zero-flux borders) for every other
// pixel. Solved by conjugate gradients preconditioned with a geometric multigrid V-cycle.
//
// The V-cycle (Trottenberg, Oosterlee & Schüller 2001, "Multigrid", ch. 2):
// - smoothing: two red-black Gauss–Seidel sweeps before the coarse correction (red, black, red,
//   black) and two after in the reverse order (black, red, black, red), so the V-cycle is a
//   symmetric operator of the residual and CG may use it (Tatebe 1993);
// - restriction: a coarse cell receives the sum of its four children's residuals; prolongation:
//   injection, its transpose;
// - coarse operators: the same unit 5-point stencil rediscretised on each coarser grid (the
//   Galerkin operator of this restriction/prolongation pair is twice as stiff: 55 instead of 17
//   CG iterations on the benchmark's map);
// - a coarse cell is free only when all its children are (fixed when any child is), so every
//   level keeps Dirichlet conditions where the fine grid has them. Making it free when any child
//   is free (so thin scribbles vanish on coarse grids) needed 38–51 instead of 10–21 iterations
//   on the benchmark's map, a line pair and scattered dots (docs/painting.md);
// - the coarsest grid (at most 16 × 16 or 4 pixels across) gets 40 symmetric Gauss–Seidel sweeps.
//
// The hierarchy is stored in float (half the memory traffic of double); CG itself runs in double
// and uses the Polak–Ribière form of β (Notay 2000, "Flexible conjugate gradients"), which stays
// robust when the float preconditioner is symmetric only up to rounding.
//
// Every grid is padded with one ghost cell on each side that stays 0, and a correction is 0 on
// fixed cells, so a stencil sums its four neighbours without tests; `diag` (the number of
// neighbours inside the grid, 0 for fixed cells) encodes the zero-flux borders. Loops run over
// rows in parallel (TBB); sums are formed per row and added in row order, so the result does
// not depend on the thread count.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "filters/simd.h"
#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

constexpr int kSmoothingSweeps = 2;  // red-black sweeps before and after the coarse correction
constexpr int kCoarsestSweeps = 40;  // symmetric sweeps on the coarsest grid
constexpr int kCoarsestSide = 4;     // stop coarsening at this shorter side …
constexpr int kCoarsestCells = 256;  // … or at this many cells

// An uninitialised array (the solver writes every element it reads, in parallel: first touch
// by the thread that uses the memory, no serial zero fill).
template <class T>
class Buffer {
  public:
    Buffer() = default;
    explicit Buffer(std::size_t n) : m_data(new T[n]), m_size(n) {}
    T* data() { return m_data.get(); }
    const T* data() const { return m_data.get(); }
    T& operator[](std::size_t i) { return m_data[i]; }
    const T& operator[](std::size_t i) const { return m_data[i]; }
    std::size_t size() const { return m_size; }

  private:
    std::unique_ptr<T[]> m_data;
    std::size_t m_size = 0;
};

// Runs fn(y) for every row; in parallel when the grid is large enough to pay for it.
template <class Fn>
void forRows(int w, int h, const Fn& fn) {
    if (std::int64_t(w) * h < 32768) {
        for (int y = 0; y < h; ++y) fn(y);
        return;
    }
    const int grain = std::max(1, 16384 / std::max(w, 1));
    tbb::parallel_for(tbb::blocked_range<int>(0, h, grain), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) fn(y);
    });
}

// One level of the hierarchy on a padded (w + 2) × (h + 2) grid.
struct Level {
    int w = 0, h = 0;
    std::size_t stride = 0;
    Buffer<float> diag;  // neighbours inside the grid (2 … 4) for free cells; 0 fixed or ghost
    Buffer<float> inv;   // 1 / diag, or 0
    Buffer<float> e;     // the correction (0 on fixed and ghost cells)
    Buffer<float> r;     // the right-hand side (0 on fixed and ghost cells)

    Level(int width, int height)
        : w(width),
          h(height),
          stride(std::size_t(width) + 2),
          diag(cells()),
          inv(cells()),
          e(cells()),
          r(cells()) {}
    std::size_t cells() const { return stride * (std::size_t(h) + 2); }
    // The padded index of pixel (x, y); x may be -1 or w, y -1 or h (ghosts).
    std::size_t at(int x, int y) const { return std::size_t(y + 1) * stride + std::size_t(x + 1); }
    // Sets the neighbour counts of a row from a free flag per pixel, zeroes its maps.
    template <class IsFree>
    void initRow(int y, const IsFree& isFree) {
        const float rowDegree = 4.0f - float(y == 0) - float(y == h - 1);
        const std::size_t i0 = at(0, y);
        for (int x = 0; x < w; ++x) {
            const float d = isFree(x) ? rowDegree - float(x == 0) - float(x == w - 1) : 0.0f;
            diag[i0 + std::size_t(x)] = d;
            inv[i0 + std::size_t(x)] = d > 0.0f ? 1.0f / d : 0.0f;
            e[i0 + std::size_t(x)] = 0.0f;
            r[i0 + std::size_t(x)] = 0.0f;
        }
    }
    // Zeroes the ghost ring of every map.
    void initGhosts() {
        for (Buffer<float>* b : {&diag, &inv, &e, &r}) {
            std::fill(b->data(), b->data() + stride, 0.0f);
            std::fill(b->data() + at(-1, h), b->data() + cells(), 0.0f);
            for (int y = 0; y < h; ++y) (*b)[at(-1, y)] = (*b)[at(w, y)] = 0.0f;
        }
    }
};

// Builds the hierarchy below `fine`: halve until small; a coarse cell is free only when every
// child inside the grid is.
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

// e ≈ A⁻¹ r on level l and below; a symmetric linear operator of r.
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

// Conjugate-gradient row kernels in double, 4 lanes at a time; each returns its row's sums.
typedef double VecD __attribute__((vector_size(32)));
typedef float VecF4 __attribute__((vector_size(16)));

[[gnu::always_inline]] inline void loadD(VecD& v, const double* p) {
    std::memcpy(&v, p, sizeof v);
}
[[gnu::always_inline]] inline void storeD(double* p, const VecD& v) {
    std::memcpy(p, &v, sizeof v);
}
// Vectors travel by reference only (no function's ABI depends on AVX being enabled).
[[gnu::always_inline]] inline void loadWiden(VecD& v, const float* p) {
    VecF4 f;
    std::memcpy(&f, p, sizeof f);
    v = __builtin_convertvector(f, VecD);
}
[[gnu::always_inline]] inline double laneSum(const VecD& v) {
    return (v[0] + v[1]) + (v[2] + v[3]);
}

// Ap = A p over a row (0 on fixed cells); returns Σ p·Ap.
GLINT_SIMD_CLONES double applyRow(double* Ap, const double* p, const float* diag,
                                  std::size_t stride, int w) {
    VecD acc{};
    int x = 0;
    for (; x + 4 <= w; x += 4) {
        VecD c, left, right, up, down;
        loadD(c, p + x);
        loadD(left, p + x - 1);
        loadD(right, p + x + 1);
        loadD(up, p + x - stride);
        loadD(down, p + x + stride);
        VecD dg;
        loadWiden(dg, diag + x);
        const VecD a = dg > 0.0 ? dg * c - ((left + right) + (up + down)) : VecD{};
        storeD(Ap + x, a);
        acc += c * a;
    }
    double s = laneSum(acc);
    for (; x < w; ++x) {
        Ap[x] = diag[x] > 0.0f
                    ? double(diag[x]) * p[x] - p[x - 1] - p[x + 1] - p[x - stride] - p[x + stride]
                    : 0.0;
        s += p[x] * Ap[x];
    }
    return s;
}

// x += αp, r −= αAp, rf = r in float (the preconditioner's input); returns Σ r².
GLINT_SIMD_CLONES double updateRow(double* x, double* r, float* rf, const double* p,
                                   const double* Ap, double alpha, int w) {
    VecD acc{};
    int i = 0;
    for (; i + 4 <= w; i += 4) {
        VecD xv, rv, pv, av;
        loadD(xv, x + i);
        loadD(rv, r + i);
        loadD(pv, p + i);
        loadD(av, Ap + i);
        xv += alpha * pv;
        rv -= alpha * av;
        storeD(x + i, xv);
        storeD(r + i, rv);
        const VecF4 narrow = __builtin_convertvector(rv, VecF4);
        std::memcpy(rf + i, &narrow, sizeof narrow);
        acc += rv * rv;
    }
    double s = laneSum(acc);
    for (; i < w; ++i) {
        x[i] += alpha * p[i];
        r[i] -= alpha * Ap[i];
        rf[i] = float(r[i]);
        s += r[i] * r[i];
    }
    return s;
}

// Returns Σ r·z and Σ z·Ap (z = the preconditioned residual, in float).
GLINT_SIMD_CLONES std::pair<double, double> dotsRow(const double* r, const float* z,
                                                    const double* Ap, int w) {
    VecD rz{}, zAp{};
    int i = 0;
    for (; i + 4 <= w; i += 4) {
        VecD rv, av;
        loadD(rv, r + i);
        loadD(av, Ap + i);
        VecD zv;
        loadWiden(zv, z + i);
        rz += rv * zv;
        zAp += zv * av;
    }
    double a = laneSum(rz), b = laneSum(zAp);
    for (; i < w; ++i) {
        a += r[i] * double(z[i]);
        b += double(z[i]) * Ap[i];
    }
    return {a, b};
}

// p = z + βp.
GLINT_SIMD_CLONES void directionRow(double* p, const float* z, double beta, int w) {
    int i = 0;
    for (; i + 4 <= w; i += 4) {
        VecD pv, zv;
        loadD(pv, p + i);
        loadWiden(zv, z + i);
        storeD(p + i, zv + beta * pv);
    }
    for (; i < w; ++i) p[i] = double(z[i]) + beta * p[i];
}

// Per-row partial sums added in row order (deterministic for any thread count).
class RowSums {
  public:
    explicit RowSums(int h) : m_a(std::size_t(h), 0.0), m_b(std::size_t(h), 0.0) {}
    double& a(int y) { return m_a[std::size_t(y)]; }
    double& b(int y) { return m_b[std::size_t(y)]; }
    double totalA() const { return total(m_a); }
    double totalB() const { return total(m_b); }

  private:
    static double total(const std::vector<double>& v) {
        double s = 0.0;
        for (double x : v) s += x;
        return s;
    }
    std::vector<double> m_a, m_b;
};

}  // namespace

Image diffuseWeights(const Image& values, const Image& fixed, const DiffusionOptions& options,
                     const ProgressFn& progress) {
    if (values.channels() != 1 || !values.sameShape(fixed))
        throw Error(ErrorKind::InvalidArgument,
                    "diffusion needs a 1-channel value map and a fixed-pixel mask of the same size",
                    {}, "diffusion");
    if (!(options.tolerance > 0.0 && options.tolerance < 1.0) || options.maxIterations < 1)
        throw Error(ErrorKind::InvalidArgument,
                    "diffusion tolerance must be in (0, 1) and maxIterations >= 1", {},
                    "diffusion");
    const int w = values.width(), h = values.height();
    const std::size_t n = values.pixelCount();
    const float* v = values.data().data();
    const float* f = fixed.data().data();
    std::size_t fixedCount = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!(f[i] > 0.0f)) continue;
        ++fixedCount;
        if (!std::isfinite(v[i]))
            throw Error(ErrorKind::InvalidArgument,
                        "the fixed value at pixel (" + std::to_string(i % std::size_t(w)) + ", " +
                            std::to_string(i / std::size_t(w)) + ") is not finite",
                        {}, "diffusion");
    }
    if (fixedCount == 0)
        throw Error(ErrorKind::InvalidArgument,
                    "nothing is painted: diffusion needs some fixed pixels", {}, "diffusion");
    Image out = values;
    if (fixedCount == n) {
        if (progress) progress(1.0);
        return out;
    }

    std::vector<Level> levels = buildHierarchy(w, h, f);
    Level& L = levels[0];
    const std::size_t stride = L.stride, cells = L.cells();
    // CG vectors in double on the padded grid (ghosts and fixed cells stay 0).
    Buffer<double> x(cells), r(cells), p(cells), Ap(cells);
    auto zeroGhosts = [&](Buffer<double>& b) {
        std::fill(b.data(), b.data() + stride, 0.0);
        std::fill(b.data() + L.at(-1, h), b.data() + cells, 0.0);
        for (int y = 0; y < h; ++y) b[L.at(-1, y)] = b[L.at(w, y)] = 0.0;
    };
    for (Buffer<double>* b : {&x, &r, &p, &Ap}) zeroGhosts(*b);
    RowSums sums(h);

    // x₀: the given values clamped to [0, 1] on free pixels; r₀ = b − A x₀ where b holds the
    // fixed neighbours' values; both 0 on fixed pixels.
    forRows(w, h, [&](int y) {
        const float* vr = v + std::size_t(y) * std::size_t(w);
        const std::size_t i0 = L.at(0, y);
        for (int xx = 0; xx < w; ++xx) {
            const bool free = L.diag[i0 + std::size_t(xx)] > 0.0f;
            x[i0 + std::size_t(xx)] =
                free && std::isfinite(vr[xx]) ? std::clamp(double(vr[xx]), 0.0, 1.0) : 0.0;
        }
    });
    forRows(w, h, [&](int y) {
        const float* vr = v + std::size_t(y) * std::size_t(w);
        const float* fr = f + std::size_t(y) * std::size_t(w);
        const std::size_t i0 = L.at(0, y);
        double bb = 0.0, rr = 0.0;
        for (int xx = 0; xx < w; ++xx) {
            const std::size_t i = i0 + std::size_t(xx);
            if (L.diag[i] == 0.0f) {
                r[i] = p[i] = Ap[i] = 0.0;
                continue;
            }
            const std::size_t k = std::size_t(y) * std::size_t(w) + std::size_t(xx);
            double bi = 0.0;
            if (xx > 0 && fr[xx - 1] > 0.0f) bi += vr[xx - 1];
            if (xx + 1 < w && fr[xx + 1] > 0.0f) bi += vr[xx + 1];
            if (y > 0 && f[k - std::size_t(w)] > 0.0f) bi += v[k - std::size_t(w)];
            if (y + 1 < h && f[k + std::size_t(w)] > 0.0f) bi += v[k + std::size_t(w)];
            const double ri = bi - (double(L.diag[i]) * x[i] - x[i - 1] - x[i + 1] - x[i - stride] -
                                    x[i + stride]);
            r[i] = ri;
            L.r[i] = float(ri);
            bb += bi * bi;
            rr += ri * ri;
        }
        sums.a(y) = bb;
        sums.b(y) = rr;
    });
    const double bNorm = std::sqrt(sums.totalA());
    double rNorm = std::sqrt(sums.totalB());

    auto writeResult = [&] {
        forRows(w, h, [&](int y) {
            float* o = out.row(y);
            const std::size_t i0 = L.at(0, y);
            for (int xx = 0; xx < w; ++xx)
                if (L.diag[i0 + std::size_t(xx)] > 0.0f)
                    o[xx] = float(std::clamp(x[i0 + std::size_t(xx)], 0.0, 1.0));
        });
        if (progress) progress(1.0);
        return out;
    };
    if (bNorm == 0.0) {
        // Every fixed value is 0: so is the solution.
        std::fill(x.data(), x.data() + cells, 0.0);
        return writeResult();
    }
    const double target = options.tolerance * bNorm;
    if (rNorm <= target) return writeResult();
    const double r0 = rNorm;

    // Preconditioned conjugate gradients (Saad 2003, Alg. 9.1; β after Polak–Ribière).
    // z = M r lives in L.e; p₀ = z₀.
    vCycle(levels, 0);
    forRows(w, h, [&](int y) {
        const std::size_t i0 = L.at(0, y);
        double rz = 0.0;
        for (std::size_t i = i0; i < i0 + std::size_t(w); ++i) {
            p[i] = L.e[i];
            rz += r[i] * double(L.e[i]);
        }
        sums.a(y) = rz;
    });
    double rz = sums.totalA();
    for (int it = 0;; ++it) {
        if (it == options.maxIterations)
            throw Error(ErrorKind::Numeric,
                        "diffusion did not converge in " + std::to_string(options.maxIterations) +
                            " iterations (relative residual " + std::to_string(rNorm / bNorm) +
                            ", wanted " + std::to_string(options.tolerance) + ")",
                        {}, "diffusion");
        // Ap and p·Ap.
        forRows(w, h, [&](int y) {
            const std::size_t i0 = L.at(0, y);
            sums.a(y) = applyRow(Ap.data() + i0, p.data() + i0, L.diag.data() + i0, stride, w);
        });
        const double alpha = rz / sums.totalA();
        // x += αp, r −= αAp, ‖r‖², and r for the preconditioner.
        forRows(w, h, [&](int y) {
            const std::size_t i0 = L.at(0, y);
            sums.a(y) = updateRow(x.data() + i0, r.data() + i0, L.r.data() + i0, p.data() + i0,
                                  Ap.data() + i0, alpha, w);
        });
        rNorm = std::sqrt(sums.totalA());
        if (rNorm <= target) break;
        if (progress &&
            !progress(std::clamp(std::log(r0 / rNorm) / std::log(r0 / target), 0.0, 0.999)))
            throw Error(ErrorKind::Cancelled, "diffusion cancelled");
        vCycle(levels, 0);
        // β = z·(r_new − r_old) / rz_old = −α z·Ap / rz_old; then p = z + βp.
        forRows(w, h, [&](int y) {
            const std::size_t i0 = L.at(0, y);
            std::tie(sums.a(y), sums.b(y)) =
                dotsRow(r.data() + i0, L.e.data() + i0, Ap.data() + i0, w);
        });
        const double beta = -alpha * sums.totalB() / rz;
        rz = sums.totalA();
        forRows(w, h, [&](int y) {
            const std::size_t i0 = L.at(0, y);
            directionRow(p.data() + i0, L.e.data() + i0, beta, w);
        });
    }
    return writeResult();
}

}  // namespace glint::denoise
