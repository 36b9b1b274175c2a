// Poisson-diffusion blending: the steady state of the heat equation with the painted pixels held
// fixed, i.e. the discrete Laplace equation (5-point stencil, zero-flux borders) for every other
// pixel. Solved by conjugate gradients preconditioned with a geometric multigrid V-cycle
// (symmetric: red-black Gauss–Seidel red→black before, black→red after, restriction by summing
// the four children, prolongation by injection, its transpose; the coarse operator is the same
// stencil rediscretised on the coarse grid — the Galerkin operator of that pair would be twice
// as stiff and takes 55 instead of 14 iterations on a 1024² map). A coarse cell is fixed when any
// of its children is, so every level keeps Dirichlet conditions and stays non-singular.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// One level of the hierarchy.
struct Level {
    int w = 0, h = 0;
    std::vector<unsigned char> free;  // 1 where the value is unknown
    std::vector<unsigned char> deg;   // neighbours inside the grid (2 … 4)
    std::vector<double> e, r;         // correction and right-hand side / residual
    std::size_t at(int x, int y) const { return std::size_t(y) * std::size_t(w) + std::size_t(x); }
};

template <class Fn>
void rows(int h, const Fn& fn) {
    tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end(); ++y) fn(y);
    });
}

template <class Fn>
double sumRows(int h, const Fn& fn) {
    // Row sums in parallel, added in row order: deterministic for any thread count.
    std::vector<double> partial(std::size_t(h), 0.0);
    rows(h, [&](int y) { partial[std::size_t(y)] = fn(y); });
    double s = 0.0;
    for (double v : partial) s += v;
    return s;
}

// Σ of the free neighbours' values of (x, y).
inline double neighbourSum(const Level& L, const std::vector<double>& v, int x, int y) {
    double s = 0.0;
    const std::size_t i = L.at(x, y);
    if (x > 0 && L.free[i - 1]) s += v[i - 1];
    if (x + 1 < L.w && L.free[i + 1]) s += v[i + 1];
    if (y > 0 && L.free[i - std::size_t(L.w)]) s += v[i - std::size_t(L.w)];
    if (y + 1 < L.h && L.free[i + std::size_t(L.w)]) s += v[i + std::size_t(L.w)];
    return s;
}

// out = A v on the free cells (0 elsewhere).
void applyOperator(const Level& L, const std::vector<double>& v, std::vector<double>& out) {
    rows(L.h, [&](int y) {
        for (int x = 0; x < L.w; ++x) {
            const std::size_t i = L.at(x, y);
            out[i] = L.free[i] ? L.deg[i] * v[i] - neighbourSum(L, v, x, y) : 0.0;
        }
    });
}

// One Gauss–Seidel half-sweep over the cells of one colour ((x + y) % 2 == parity).
void smoothColour(Level& L, int parity) {
    rows(L.h, [&](int y) {
        for (int x = (y + parity) & 1; x < L.w; x += 2) {
            const std::size_t i = L.at(x, y);
            if (!L.free[i]) continue;
            L.e[i] = (L.r[i] + neighbourSum(L, L.e, x, y)) / double(L.deg[i]);
        }
    });
}

// e ≈ A⁻¹ r on level l (and below), symmetric in r.
void vCycle(std::vector<Level>& levels, std::size_t l) {
    Level& L = levels[l];
    std::fill(L.e.begin(), L.e.end(), 0.0);
    if (l + 1 == levels.size()) {
        // Coarsest: symmetric Gauss–Seidel sweeps (a symmetric operator of r).
        for (int it = 0; it < 40; ++it) {
            smoothColour(L, 0);
            smoothColour(L, 1);
            smoothColour(L, 1);
            smoothColour(L, 0);
        }
        return;
    }
    smoothColour(L, 0);
    smoothColour(L, 1);
    // Residual, restricted by summing the free children into free coarse cells.
    std::vector<double> res(L.e.size());
    applyOperator(L, L.e, res);
    Level& C = levels[l + 1];
    rows(C.h, [&](int Y) {
        for (int X = 0; X < C.w; ++X) {
            const std::size_t I = C.at(X, Y);
            double s = 0.0;
            if (C.free[I])
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int x = 2 * X + dx, y = 2 * Y + dy;
                        if (x >= L.w || y >= L.h) continue;
                        const std::size_t i = L.at(x, y);
                        if (L.free[i]) s += L.r[i] - res[i];
                    }
            C.r[I] = s;
        }
    });
    vCycle(levels, l + 1);
    // Prolongation by injection.
    rows(L.h, [&](int y) {
        for (int x = 0; x < L.w; ++x) {
            const std::size_t i = L.at(x, y);
            const std::size_t I = C.at(x / 2, y / 2);
            if (L.free[i] && C.free[I]) L.e[i] += C.e[I];
        }
    });
    smoothColour(L, 1);
    smoothColour(L, 0);
}

double dot(const Level& L, const std::vector<double>& a, const std::vector<double>& b) {
    return sumRows(L.h, [&](int y) {
        double s = 0.0;
        for (std::size_t i = L.at(0, y), end = i + std::size_t(L.w); i < end; ++i) s += a[i] * b[i];
        return s;
    });
}

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
    std::vector<Level> levels(1);
    Level& L0 = levels[0];
    L0.w = w;
    L0.h = h;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    L0.free.assign(n, 0);
    std::size_t fixedCount = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const bool isFixed = fixed.data()[i] > 0.0f;
        L0.free[i] = isFixed ? 0 : 1;
        fixedCount += isFixed;
        if (isFixed && !std::isfinite(values.data()[i]))
            throw Error(ErrorKind::InvalidArgument, "a fixed value is not finite", {}, "diffusion");
    }
    if (fixedCount == 0)
        throw Error(ErrorKind::InvalidArgument,
                    "nothing is painted: diffusion needs some fixed pixels", {}, "diffusion");
    Image out = values;
    if (fixedCount == n) return out;

    // The hierarchy: halve until the grid is small; coarse cells are free only when all their
    // children are.
    while (true) {
        const Level& F = levels.back();
        if (std::min(F.w, F.h) <= 4 || F.w * F.h <= 256) break;
        Level C;
        C.w = (F.w + 1) / 2;
        C.h = (F.h + 1) / 2;
        C.free.assign(std::size_t(C.w) * std::size_t(C.h), 0);
        for (int Y = 0; Y < C.h; ++Y)
            for (int X = 0; X < C.w; ++X) {
                bool allFree = true;
                for (int dy = 0; dy < 2; ++dy)
                    for (int dx = 0; dx < 2; ++dx) {
                        const int x = 2 * X + dx, y = 2 * Y + dy;
                        if (x < F.w && y < F.h) allFree = allFree && F.free[F.at(x, y)];
                    }
                C.free[C.at(X, Y)] = allFree ? 1 : 0;
            }
        levels.push_back(std::move(C));
    }
    for (Level& L : levels) {
        const std::size_t m = std::size_t(L.w) * std::size_t(L.h);
        L.deg.assign(m, 0);
        L.e.assign(m, 0.0);
        L.r.assign(m, 0.0);
        for (int y = 0; y < L.h; ++y)
            for (int x = 0; x < L.w; ++x)
                L.deg[L.at(x, y)] =
                    static_cast<unsigned char>((x > 0) + (x + 1 < L.w) + (y > 0) + (y + 1 < L.h));
    }

    // b: the fixed neighbours' values; x: the given values as the first guess (clamped).
    Level& L = levels[0];
    std::vector<double> b(n, 0.0), x(n, 0.0), r(n), z(n), p(n), Ap(n);
    for (int y = 0; y < h; ++y)
        for (int xx = 0; xx < w; ++xx) {
            const std::size_t i = L.at(xx, y);
            if (!L.free[i]) continue;
            const float v = values.data()[i];
            x[i] = std::isfinite(v) ? std::clamp(double(v), 0.0, 1.0) : 0.0;
            double s = 0.0;
            if (xx > 0 && !L.free[i - 1]) s += values.data()[i - 1];
            if (xx + 1 < w && !L.free[i + 1]) s += values.data()[i + 1];
            if (y > 0 && !L.free[i - std::size_t(w)]) s += values.data()[i - std::size_t(w)];
            if (y + 1 < h && !L.free[i + std::size_t(w)]) s += values.data()[i + std::size_t(w)];
            b[i] = s;
        }

    // Preconditioned conjugate gradients (Saad 2003, Alg. 9.1).
    applyOperator(L, x, Ap);
    for (std::size_t i = 0; i < n; ++i) r[i] = L.free[i] ? b[i] - Ap[i] : 0.0;
    const double bNorm = std::sqrt(dot(L, b, b));
    if (bNorm == 0.0) {
        // Every fixed value is 0: so is the solution.
        for (std::size_t i = 0; i < n; ++i)
            if (L.free[i]) out.data()[i] = 0.0f;
        if (progress) progress(1.0);
        return out;
    }
    const double target = options.tolerance * std::max(bNorm, 1e-300);
    double rNorm = std::sqrt(dot(L, r, r));
    const double r0 = rNorm;
    auto precondition = [&] {
        L.r = r;
        vCycle(levels, 0);
        z = L.e;
    };
    if (rNorm > target) {
        precondition();
        p = z;
        double rz = dot(L, r, z);
        int it = 0;
        for (; it < options.maxIterations && rNorm > target; ++it) {
            applyOperator(L, p, Ap);
            const double alpha = rz / dot(L, p, Ap);
            for (std::size_t i = 0; i < n; ++i) {
                x[i] += alpha * p[i];
                r[i] -= alpha * Ap[i];
            }
            rNorm = std::sqrt(dot(L, r, r));
            if (progress && r0 > target &&
                !progress(std::clamp(std::log(r0 / rNorm) / std::log(r0 / target), 0.0, 0.999)))
                throw Error(ErrorKind::Cancelled, "diffusion cancelled");
            if (rNorm <= target) break;
            precondition();
            const double rzNew = dot(L, r, z);
            const double beta = rzNew / rz;
            rz = rzNew;
            for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
        }
        if (!(rNorm <= target))
            throw Error(ErrorKind::Numeric,
                        "diffusion did not converge in " + std::to_string(options.maxIterations) +
                            " iterations (relative residual " + std::to_string(rNorm / bNorm) + ")",
                        {}, "diffusion");
    }
    if (progress) progress(1.0);
    for (std::size_t i = 0; i < n; ++i)
        if (L.free[i]) out.data()[i] = float(std::clamp(x[i], 0.0, 1.0));
    return out;
}

}  // namespace glint::denoise
