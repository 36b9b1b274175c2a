// The geometric multigrid V-cycle that preconditions the conjugate gradients of
// diffuseWeights (diffusion.cpp), on the grids of the discrete Laplace equation with the painted
// pixels held fixed.
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
// Every grid is padded with one ghost cell on each side that stays 0, and a correction is 0 on
// fixed cells, so a stencil sums its four neighbours without tests; `diag` (the number of
// neighbours inside the grid, 0 for fixed cells) encodes the zero-flux borders. Loops run over
// rows in parallel (TBB).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace glint::denoise::multigrid {

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

// Builds the hierarchy below a fine grid of w × h pixels (`fixed` nonzero where a pixel is
// held): halve until small; a coarse cell is free only when every child inside the grid is.
std::vector<Level> buildHierarchy(int w, int h, const float* fixed);

// e ≈ A⁻¹ r on level l and below; a symmetric linear operator of r.
void vCycle(std::vector<Level>& levels, std::size_t l);

}  // namespace glint::denoise::multigrid
