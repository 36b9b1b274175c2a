// Poisson-diffusion blending: the steady state of the heat equation with the painted pixels held
// fixed, i.e. the discrete Laplace equation (5-point stencil, zero-flux borders) for every other
// pixel. Solved by conjugate gradients preconditioned with a geometric multigrid V-cycle
// (composite/multigrid.{h,cpp}).
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

#include "composite/multigrid.h"
#include "filters/simd.h"
#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

using multigrid::Buffer;
using multigrid::buildHierarchy;
using multigrid::forRows;
using multigrid::Level;
using multigrid::vCycle;

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
