// Benchmarks of cross-bilateral, guided, nlmeans and the feature prefilter on a deterministic
// 1024×1024 RGB frame with all feature and variance layers, 2 TBB threads; OpenCV's
// bilateralFilter, ximgproc::guidedFilter and fastNlMeansDenoisingColored run side by side
// (2 threads) when the benchmark was built with OpenCV. Figures: docs/denoise-features.md.
//
//   build/bin/bench_denoise_b [--size=1024] [--benchmark_filter=...]
#include <benchmark/benchmark.h>
#include <sys/resource.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>

#include "glint/denoise/filter.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"

#ifdef GLINT_BENCH_OPENCV
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/photo.hpp>
#include <opencv2/ximgproc/edge_filter.hpp>
#endif

namespace {

using namespace glint;
using namespace glint::denoise;

int g_size = 1024;

// A smooth colour pattern with rectangles of different albedo, normal and depth, plus Gaussian
// noise of sigma 0.05 (variance layer 0.0025) in colour and 0.02 in the features.
const FrameBuffers& frame() {
    static const FrameBuffers f = [] {
        const int n = g_size;
        FrameBuffers fb(n, n);
        Image albedo(n, n, 3), normal(n, n, 3), depth(n, n, 1);
        std::mt19937 rng(1);
        std::normal_distribution<float> noise(0.0f, 1.0f);
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const int cell = ((x / 97) + 3 * (y / 131)) % 5;
                const float shade =
                    0.5f + 0.4f * std::sin(float(x) * 0.01f) * std::cos(float(y) * 0.013f);
                for (int c = 0; c < 3; ++c) {
                    const float a = 0.2f + 0.15f * float((cell + c) % 5);
                    albedo(x, y, c) = a + 0.02f * noise(rng);
                    fb.color()(x, y, c) = a * shade + 0.05f * noise(rng);
                    normal(x, y, c) = (c == cell % 3 ? 1.0f : 0.0f) + 0.02f * noise(rng);
                }
                depth(x, y, 0) = 10.0f + float(cell) + 0.02f * noise(rng);
            }
        fb.set(Layer::Albedo, albedo);
        fb.set(Layer::Normal, normal);
        fb.set(Layer::Depth, depth);
        fb.set(Layer::Variance, Image(n, n, 3, 0.0025f));
        fb.set(Layer::AlbedoVariance, Image(n, n, 3, 0.0004f));
        fb.set(Layer::NormalVariance, Image(n, n, 3, 0.0004f));
        fb.set(Layer::DepthVariance, Image(n, n, 1, 0.0004f));
        return fb;
    }();
    return f;
}

// CPU seconds used so far by the whole process (all threads).
double processCpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// Runs `body` per iteration and reports proc_cpu_ms: CPU time of all threads per iteration, a
// figure that a loaded machine inflates much less than wall time (idle 2-thread wall time is
// about half of it when both threads are busy).
template <class Body>
void timed(benchmark::State& state, const Body& body) {
    const double t0 = processCpuSeconds();
    for (auto _ : state) body();
    state.counters["proc_cpu_ms"] =
        1e3 * (processCpuSeconds() - t0) / double(std::max<int64_t>(1, state.iterations()));
}

void runFilter(benchmark::State& state, const char* name, const ParamValues& params) {
    const Filter& filter = findFilter(name);
    const FrameBuffers& f = frame();
    timed(state, [&] {
        Image out = applyFilter(filter, f, params);
        benchmark::DoNotOptimize(out.data().data());
    });
}

void BM_GuidedLuminance_r8(benchmark::State& s) {
    runFilter(s, "guided", {{"radius", 8}, {"eps", 1e-2}, {"guide", 0}});
}
void BM_GuidedAlbedoRGB_r8(benchmark::State& s) {
    runFilter(s, "guided", {{"radius", 8}, {"eps", 1e-2}, {"guide", 1}});
}
void BM_NlMeans_7_21(benchmark::State& s) {
    runFilter(s, "nlmeans", {{"patchRadius", 3}, {"searchRadius", 10}, {"strength", 0.45}});
}
void BM_CrossBilateral_d31(benchmark::State& s) {
    runFilter(s, "cross-bilateral", {{"radius", 15}, {"sigmaS", 5.0}});
}
void BM_Prefilter_r5(benchmark::State& state) {
    const FrameBuffers& f = frame();
    timed(state, [&] {
        FrameBuffers out = prefilterFeatures(f);
        benchmark::DoNotOptimize(out.color().data().data());
    });
}

BENCHMARK(BM_GuidedLuminance_r8)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GuidedAlbedoRGB_r8)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NlMeans_7_21)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_CrossBilateral_d31)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK(BM_Prefilter_r5)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

#ifdef GLINT_BENCH_OPENCV
cv::Mat colorMat() {
    const Image& c = frame().color();
    cv::Mat m(c.height(), c.width(), CV_32FC3);
    std::memcpy(m.data, c.data().data(), c.data().size() * sizeof(float));
    return m;
}

void BM_OpenCV_GuidedFilterRGB_r8(benchmark::State& state) {
    const cv::Mat src = colorMat();
    cv::Mat dst;
    timed(state, [&] { cv::ximgproc::guidedFilter(src, src, dst, 8, 1e-2); });
}
void BM_OpenCV_GuidedFilterGrey_r8(benchmark::State& state) {
    const cv::Mat src = colorMat();
    cv::Mat grey, dst;
    cv::cvtColor(src, grey, cv::COLOR_RGB2GRAY);
    timed(state, [&] { cv::ximgproc::guidedFilter(grey, src, dst, 8, 1e-2); });
}
void BM_OpenCV_FastNlMeansColored8bit_7_21(benchmark::State& state) {
    cv::Mat src8, dst;
    colorMat().convertTo(src8, CV_8UC3, 255.0);
    timed(state, [&] { cv::fastNlMeansDenoisingColored(src8, dst, 10.0f, 10.0f, 7, 21); });
}
void BM_OpenCV_BilateralFloat_d31(benchmark::State& state) {
    const cv::Mat src = colorMat();
    cv::Mat dst;
    timed(state, [&] { cv::bilateralFilter(src, dst, 31, 0.1, 5.0); });
}
BENCHMARK(BM_OpenCV_GuidedFilterRGB_r8)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenCV_GuidedFilterGrey_r8)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenCV_FastNlMeansColored8bit_7_21)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(BM_OpenCV_BilateralFloat_d31)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
#endif

}  // namespace

int main(int argc, char** argv) {
    // Our own flag first (--size=N), the rest goes to Google Benchmark.
    int out = 1;
    for (int i = 1; i < argc; ++i) {
        if (std::strncmp(argv[i], "--size=", 7) == 0) {
            g_size = std::atoi(argv[i] + 7);
            if (g_size < 16 || g_size > 8192) {
                std::fprintf(stderr, "bench_denoise_b: --size expects 16..8192\n");
                return 2;
            }
        } else {
            argv[out++] = argv[i];
        }
    }
    argc = out;
    tbb::global_control threads(tbb::global_control::max_allowed_parallelism, 2);
#ifdef GLINT_BENCH_OPENCV
    cv::setNumThreads(2);
#endif
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
