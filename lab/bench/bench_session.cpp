// Painting-session benchmarks (figures in docs/painting.md, "Speed") on a SIZE × SIZE frame
// (default 1024) with 2 TBB threads:
// - Dab64_ThreeLayers: one brush dab of size 64 inside an open stroke, including the composite
//   update over three layers (the stroke restarts every 256 dabs, untimed);
// - Stroke100Dabs / UndoStroke: a whole stroke (begin, 100 dabs, end: the undo step's crops) and
//   undoing it;
// - Diffusion: Poisson diffusion (diffuseWeights, multigrid-preconditioned CG) of a weight map
//   with realistic scribbles: two soft strokes of 1, an erased border band, scattered dabs of 0;
// - EigenCG_Diagonal (and EigenCG_IncompleteCholesky with --ichol, about 80 s): Eigen 3.4's
//   ConjugateGradient on the same equations and tolerance, for comparison.
// - PrepareReapply_Prefiltered/0 and /1: what the studio's worker does with a new render under a
//   session with feature prefiltering on (1 layer; its output given): Session::prepareReapply
//   prefiltering the albedo, normal and depth itself (/0, what the studio did before
//   2026-11-30: the features were then prefiltered twice, once for the filters) or keeping the
//   filter input it is handed (/1, a copy of it: what the studio does now).
// Counters: cgIterations (Glint: CG iterations; Eigen: cg.iterations()), relResidual.
//
//   build/bin/bench_session [--size=1024] [--ichol] [--benchmark_filter=...]
//                           [--benchmark_repetitions=5]
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/session.h"

namespace {

using namespace glint;
using namespace glint::denoise;

int g_size = 1024;

// A smooth noisy frame with a colour layer only (the layers' outputs are given: filters are
// timed in bench_denoise_a/b).
FrameBuffers frame(int n) {
    FrameBuffers f(n, n);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c)
                f.color()(x, y, c) =
                    0.5f + 0.3f * std::sin(0.05f * float(x + c)) * std::cos(0.03f * float(y)) +
                    0.05f * float((x * 37 + y * 11 + c * 5) % 17) / 17.0f;
    return f;
}

// A session with three layers whose outputs are scaled copies of the input; layer 0 shows at
// weight 0.5 everywhere, so every dab blends through all three.
Session& session() {
    static Session s = [] {
        Session made(frame(g_size));
        for (int l = 0; l < 3; ++l) {
            Image output = made.input().color();
            for (float& v : output.data()) v *= 0.9f + 0.05f * float(l);
            made.addLayer("gaussian", {}, std::move(output));
        }
        made.setWeights(0, Image(g_size, g_size, 1, 0.5f));
        return made;
    }();
    return s;
}

// The k-th dab position along a wavy stroke across the frame.
std::pair<double, double> dabAt(int k) {
    const double n = g_size;
    const double t = double(k % 256) / 256.0;
    return {0.1 * n + 0.8 * n * t, 0.5 * n + 0.3 * n * std::sin(6.283 * t + 0.1 * (k / 256))};
}

void BM_Dab64_ThreeLayers(benchmark::State& state) {
    Session& s = session();
    int k = 0;
    s.beginStroke(2, Brush{64.0, 0.5}, BrushMode::Add);
    for (auto _ : state) {
        const auto [x, y] = dabAt(k);
        benchmark::DoNotOptimize(s.dab(x, y));
        if (++k % 256 == 0) {
            // A fresh stroke, so dabs keep landing on pixels the stroke has not covered.
            state.PauseTiming();
            s.endStroke();
            s.undo();
            s.beginStroke(2, Brush{64.0, 0.5}, BrushMode::Add);
            state.ResumeTiming();
        }
    }
    s.endStroke();
    if (s.canUndo()) s.undo();
}
BENCHMARK(BM_Dab64_ThreeLayers)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_PrepareReapply_Prefiltered(benchmark::State& state) {
    // A render with noisy features and their variances, as prefiltering takes them.
    FrameBuffers next = frame(g_size);
    const std::pair<Layer, Layer> features[] = {{Layer::Albedo, Layer::AlbedoVariance},
                                                {Layer::Normal, Layer::NormalVariance},
                                                {Layer::Depth, Layer::DepthVariance}};
    for (const auto& [l, v] : features) {
        const int channels = l == Layer::Depth ? 1 : 3;
        Image feature(g_size, g_size, channels), variance(g_size, g_size, channels);
        for (int y = 0; y < g_size; ++y)
            for (int x = 0; x < g_size; ++x)
                for (int c = 0; c < channels; ++c) {
                    const float noise = float((x * 13 + y * 7 + c * 3) % 11) / 11.0f;
                    feature(x, y, c) = 0.4f + 0.2f * noise;
                    variance(x, y, c) = 1e-3f * (0.5f + noise);
                }
        next.set(l, std::move(feature));
        next.set(v, std::move(variance));
    }
    SessionOptions options;
    options.prefilter = true;
    Session s(next, options);
    s.addLayer("gaussian", {}, next.color());
    const Session::Snapshot snap = s.snapshot();
    const FrameBuffers filterInput = prefilterFeatures(next, options.prefilterParams);
    const bool given = state.range(0) == 1;
    for (auto _ : state) {
        Session::Reapplication r = Session::prepareReapply(
            next, {next.color()}, snap,
            given ? std::optional<FrameBuffers>(filterInput) : std::nullopt);
        benchmark::DoNotOptimize(r.composite.data().data());
    }
}
BENCHMARK(BM_PrepareReapply_Prefiltered)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_Stroke100Dabs(benchmark::State& state) {
    Session& s = session();
    for (auto _ : state) {
        s.beginStroke(1, Brush{64.0, 0.5}, BrushMode::Add);
        for (int k = 0; k < 100; ++k) {
            const auto [x, y] = dabAt(k * 2);
            s.dab(x, y);
        }
        s.endStroke();
        state.PauseTiming();
        s.undo();
        state.ResumeTiming();
    }
}
BENCHMARK(BM_Stroke100Dabs)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_UndoStroke(benchmark::State& state) {
    Session& s = session();
    for (auto _ : state) {
        state.PauseTiming();
        s.beginStroke(1, Brush{64.0, 0.5}, BrushMode::Add);
        for (int k = 0; k < 100; ++k) {
            const auto [x, y] = dabAt(k * 2);
            s.dab(x, y);
        }
        s.endStroke();
        state.ResumeTiming();
        s.undo();
    }
}
BENCHMARK(BM_UndoStroke)->Unit(benchmark::kMillisecond)->UseRealTime();

// Realistic scribbles: two soft strokes of 1, an erased border band (x < 16 or y ≥ n − 16) and
// scattered dabs of 0.
struct Scribbles {
    Image values, fixed;
};

const Scribbles& scribbles() {
    static const Scribbles s = [] {
        const int n = g_size;
        Scribbles made{Image(n, n, 1, 0.0f), Image(n, n, 1, 0.0f)};
        auto disc = [&](double cx, double cy, double r, float v) {
            for (int y = std::max(0, int(cy - r)); y < std::min(n, int(cy + r) + 1); ++y)
                for (int x = std::max(0, int(cx - r)); x < std::min(n, int(cx + r) + 1); ++x)
                    if (std::hypot(x - cx, y - cy) <= r) {
                        made.values(x, y, 0) = v;
                        made.fixed(x, y, 0) = 1.0f;
                    }
        };
        for (double t = 0.0; t < 1.0; t += 0.01) {
            disc(0.2 * n + 0.5 * n * t, 0.3 * n + 0.1 * n * std::sin(6.0 * t), 0.02 * n, 1.0f);
            disc(0.6 * n, 0.2 * n + 0.6 * n * t, 0.015 * n, 1.0f);
        }
        for (int k = 0; k < 12; ++k)
            disc(n * (0.15 + 0.07 * k), n * (0.75 + 0.1 * std::sin(k)), 0.01 * n, 0.0f);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                if (x < 16 || y >= n - 16) {
                    made.values(x, y, 0) = 0.0f;
                    made.fixed(x, y, 0) = 1.0f;
                }
        return made;
    }();
    return s;
}

void BM_Diffusion(benchmark::State& state) {
    const Scribbles& s = scribbles();
    int calls = 0;
    for (auto _ : state) {
        calls = 0;
        // One progress call per CG iteration (the last one reports 1).
        benchmark::DoNotOptimize(diffuseWeights(s.values, s.fixed, {}, [&](double) {
            ++calls;
            return true;
        }));
    }
    state.counters["cgIterations"] = calls;
}
BENCHMARK(BM_Diffusion)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same equations for Eigen: one unknown per free pixel.
struct EigenProblem {
    Eigen::SparseMatrix<double> A;
    Eigen::VectorXd b;
};

const EigenProblem& eigenProblem() {
    static const EigenProblem p = [] {
        const int n = g_size;
        const Scribbles& s = scribbles();
        std::vector<int> index(std::size_t(n) * std::size_t(n), -1);
        int m = 0;
        for (std::size_t i = 0; i < index.size(); ++i)
            if (s.fixed.data()[i] == 0.0f) index[i] = m++;
        std::vector<Eigen::Triplet<double>> t;
        EigenProblem made{Eigen::SparseMatrix<double>(m, m), Eigen::VectorXd::Zero(m)};
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const int i = index[std::size_t(y) * std::size_t(n) + std::size_t(x)];
                if (i < 0) continue;
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                int deg = 0;
                for (int k = 0; k < 4; ++k) {
                    if (nx[k] < 0 || ny[k] < 0 || nx[k] >= n || ny[k] >= n) continue;
                    ++deg;
                    const int j = index[std::size_t(ny[k]) * std::size_t(n) + std::size_t(nx[k])];
                    if (j >= 0)
                        t.emplace_back(i, j, -1.0);
                    else
                        made.b[i] += s.values(nx[k], ny[k], 0);
                }
                t.emplace_back(i, i, double(deg));
            }
        made.A.setFromTriplets(t.begin(), t.end());
        return made;
    }();
    return p;
}

template <class Solver>
void eigenCg(benchmark::State& state) {
    const EigenProblem& p = eigenProblem();
    Solver cg;
    cg.setTolerance(1e-6);  // relative residual, as DiffusionOptions::tolerance
    cg.setMaxIterations(100000);
    for (auto _ : state) {
        cg.compute(p.A);
        // solve() returns an expression: evaluating it into a vector runs the solver.
        Eigen::VectorXd x = cg.solve(p.b);
        benchmark::DoNotOptimize(x.data());
    }
    state.counters["cgIterations"] = double(cg.iterations());
    state.counters["relResidual"] = cg.error();
}

using EigenDiagonal =
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper>;
using EigenIncompleteCholesky =
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper,
                             Eigen::IncompleteCholesky<double>>;

void BM_EigenCG_Diagonal(benchmark::State& state) {
    eigenCg<EigenDiagonal>(state);
}
BENCHMARK(BM_EigenCG_Diagonal)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

void BM_EigenCG_IncompleteCholesky(benchmark::State& state) {
    eigenCg<EigenIncompleteCholesky>(state);
}

}  // namespace

int main(int argc, char** argv) {
    // Our own flags first (--size=N, --ichol), the rest goes to Google Benchmark.
    int out = 1;
    bool ichol = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strncmp(argv[i], "--size=", 7) == 0) {
            g_size = std::atoi(argv[i] + 7);
            if (g_size < 64 || g_size > 8192) {
                std::fprintf(stderr, "bench_session: --size expects 64..8192\n");
                return 2;
            }
        } else if (std::strcmp(argv[i], "--ichol") == 0) {
            ichol = true;
        } else {
            argv[out++] = argv[i];
        }
    }
    argc = out;
    if (ichol)
        benchmark::RegisterBenchmark("BM_EigenCG_IncompleteCholesky", BM_EigenCG_IncompleteCholesky)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime()
            ->Iterations(1);
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
    Eigen::setNbThreads(1);  // Eigen's CG is single-threaded unless built with OpenMP
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
