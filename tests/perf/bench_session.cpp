// bench_session: the painting speed figures of docs/painting.md on a SIZE² frame (default 1024)
// with THREADS threads (default 2): one brush dab (size 64) including the composite update over
// three layers, a whole stroke, Poisson diffusion of scribbled weights (Glint's multigrid-
// preconditioned CG), and, on the same problem, Eigen's conjugate gradients (diagonal and
// incomplete-Cholesky preconditioners) for comparison. Prints one JSON object.
//   bench_session [--size 1024] [--threads 2] [--eigen 1]
#include <tbb/global_control.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/denoise/paint.h"
#include "glint/denoise/session.h"

namespace {

using Clock = std::chrono::steady_clock;

double secondsOf(const std::function<void()>& fn) {
    const auto t0 = Clock::now();
    fn();
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// A noisy frame with a colour layer only (the filters' outputs are given, not timed).
glint::FrameBuffers frame(int n) {
    glint::FrameBuffers f(n, n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c)
                f.color()(x, y, c) =
                    0.5f + 0.3f * std::sin(0.05f * float(x + c)) * std::cos(0.03f * float(y)) +
                    0.05f * float((x * 37 + y * 11 + c * 5) % 17) / 17.0f;
    return f;
}

// Realistic scribbles: a few soft strokes of 1, an erased border band, scattered dabs.
void scribbles(int n, glint::Image& values, glint::Image& fixed) {
    values = glint::Image(n, n, 1, 0.0f);
    fixed = glint::Image(n, n, 1, 0.0f);
    auto disc = [&](double cx, double cy, double r, float v) {
        for (int y = std::max(0, int(cy - r)); y < std::min(n, int(cy + r) + 1); ++y)
            for (int x = std::max(0, int(cx - r)); x < std::min(n, int(cx + r) + 1); ++x)
                if (std::hypot(x - cx, y - cy) <= r) values(x, y, 0) = v, fixed(x, y, 0) = 1.0f;
    };
    for (double t = 0.0; t < 1.0; t += 0.01) {
        disc(0.2 * n + 0.5 * n * t, 0.3 * n + 0.1 * n * std::sin(6.0 * t), 0.02 * n, 1.0f);
        disc(0.6 * n, 0.2 * n + 0.6 * n * t, 0.015 * n, 1.0f);
    }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if (x < 16 || y > n - 16) values(x, y, 0) = 0.0f, fixed(x, y, 0) = 1.0f;
}

}  // namespace

int main(int argc, char** argv) {
    int n = 1024, threads = 2, eigen = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--size")
            n = std::stoi(argv[i + 1]);
        else if (a == "--threads")
            threads = std::stoi(argv[i + 1]);
        else if (a == "--eigen")
            eigen = std::stoi(argv[i + 1]);
        else {
            std::fprintf(stderr, "bench_session: unknown option %s\n", a.c_str());
            return 2;
        }
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    nlohmann::json out = {{"size", n}, {"threads", threads}};

    // A session with three layers (outputs given: the filters are timed elsewhere).
    glint::denoise::Session session(frame(n));
    for (int l = 0; l < 3; ++l) {
        glint::Image output = session.input().color();
        for (float& v : output.data()) v *= 0.9f + 0.05f * float(l);
        session.addLayer("gaussian", {}, std::move(output));
    }
    session.setWeights(0, glint::Image(n, n, 1, 0.5f));
    // One dab of size 64, timed one by one along a stroke (weights + composite update).
    std::vector<double> dabs;
    session.beginStroke(2, glint::denoise::Brush{64.0, 0.5}, glint::denoise::BrushMode::Add);
    for (int i = 0; i < 400; ++i) {
        const double x = 100.0 + 2.0 * i, y = 300.0 + 150.0 * std::sin(0.02 * i);
        dabs.push_back(secondsOf([&] { session.dab(x, y); }));
    }
    const double endStroke = secondsOf([&] { session.endStroke(); });
    out["dabMedianMs"] = 1e3 * median(dabs);
    out["dabMaxMs"] = 1e3 * *std::max_element(dabs.begin(), dabs.end());
    out["endStrokeMs"] = 1e3 * endStroke;
    out["beginStrokeMs"] = 1e3 * secondsOf([&] {
                               session.beginStroke(1, glint::denoise::Brush{64.0, 0.5},
                                                   glint::denoise::BrushMode::Add);
                           });
    session.endStroke();
    out["undoStrokeMs"] = 1e3 * secondsOf([&] { session.undo(); });

    // Poisson diffusion.
    glint::Image values, fixed;
    scribbles(n, values, fixed);
    std::vector<double> diffusion;
    int iterations = 0;
    for (int r = 0; r < 5; ++r) {
        int calls = 0;
        diffusion.push_back(secondsOf([&] {
            glint::denoise::diffuseWeights(values, fixed, {}, [&](double) {
                ++calls;
                return true;
            });
        }));
        iterations = calls - 1;  // one call per CG iteration, one at the end
    }
    out["diffusionSeconds"] = median(diffusion);
    out["diffusionIterations"] = iterations;

    if (eigen) {
        // The same equations for Eigen: one unknown per free pixel, relative residual 1e-6.
        std::vector<int> index(std::size_t(n) * n, -1);
        int m = 0;
        for (std::size_t i = 0; i < index.size(); ++i)
            if (fixed.data()[i] == 0.0f) index[i] = m++;
        std::vector<Eigen::Triplet<double>> t;
        Eigen::VectorXd b = Eigen::VectorXd::Zero(m);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const int i = index[std::size_t(y) * n + x];
                if (i < 0) continue;
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                int deg = 0;
                for (int k = 0; k < 4; ++k) {
                    if (nx[k] < 0 || ny[k] < 0 || nx[k] >= n || ny[k] >= n) continue;
                    ++deg;
                    const int j = index[std::size_t(ny[k]) * n + nx[k]];
                    if (j >= 0)
                        t.emplace_back(i, j, -1.0);
                    else
                        b[i] += values(nx[k], ny[k], 0);
                }
                t.emplace_back(i, i, double(deg));
            }
        Eigen::SparseMatrix<double> A(m, m);
        A.setFromTriplets(t.begin(), t.end());
        Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
        cg.setTolerance(1e-6);
        Eigen::VectorXd x;
        out["eigenCgDiagonalSeconds"] = secondsOf([&] {
            cg.compute(A);
            x = cg.solve(b);
        });
        out["eigenCgDiagonalIterations"] = int(cg.iterations());
        Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                                 Eigen::IncompleteCholesky<double>>
            icg;
        icg.setTolerance(1e-6);
        out["eigenCgIncompleteCholeskySeconds"] = secondsOf([&] {
            icg.compute(A);
            x = icg.solve(b);
        });
        out["eigenCgIncompleteCholeskyIterations"] = int(icg.iterations());
    }
    std::cout << out.dump(2) << "\n";
    return 0;
}
