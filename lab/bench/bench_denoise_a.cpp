// Benchmark of the gaussian, bilateral and bilateral-mc filters on a 1024 x 1024 RGB float image
// (issue 5 speed goals), OpenCV 4.6 side by side when available, and the accuracy-versus-samples
// curve of bilateral-mc (k N samples, k = 1..7, four pattern kinds; Banterle et al. 2012).
// Prints a table and, last, one JSON object.
//
// The machine is shared, so each of the --reps rounds runs every Glint filter immediately followed
// by its OpenCV peer (interleaved: both see the same load), and the table reports the median and
// the minimum over the rounds, plus the median of the per-round ratio Glint / OpenCV.
//
//   build/bin/bench_denoise_a [--threads 2] [--size 1024] [--reps 5] [--curve 1] [--only TEXT]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "bench_options.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"

#ifdef GLINT_BENCH_HAVE_OPENCV
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace {

using glint::FrameBuffers;
using glint::Image;
using glint::denoise::applyFilter;
using glint::denoise::findFilter;
using glint::denoise::ParamValues;

// A rendering-like test image in [0, 1]: shaded background, discs and boxes with sharp edges,
// a fine sinusoidal texture band, plus Gaussian noise of standard deviation 0.05 (fixed seed).
FrameBuffers testImage(int size) {
    FrameBuffers frame(size, size);
    Image& c = frame.color();
    std::mt19937 rng(12345);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float u = float(x) / float(size), v = float(y) / float(size);
            float rgb[3] = {0.2f + 0.3f * v, 0.25f + 0.2f * u, 0.3f};
            const float d1 = std::hypot(u - 0.3f, v - 0.35f), d2 = std::hypot(u - 0.7f, v - 0.6f);
            if (d1 < 0.18f) rgb[0] = 0.8f, rgb[1] = 0.3f - d1, rgb[2] = 0.2f;
            if (d2 < 0.22f) rgb[0] = 0.1f, rgb[1] = 0.6f, rgb[2] = 0.7f + 0.5f * (u - 0.7f);
            if (u > 0.1f && u < 0.45f && v > 0.65f && v < 0.9f) rgb[0] = rgb[1] = rgb[2] = 0.9f;
            if (v > 0.05f && v < 0.15f)
                for (float& ch : rgb) ch = 0.5f + 0.3f * std::sin(60.0f * u) * std::sin(40.0f * v);
            for (int k = 0; k < 3; ++k) c(x, y, k) = rgb[k] + noise(rng);
        }
    return frame;
}

// Wall time of one call of fn.
double secondsOf(const std::function<void()>& fn) {
    const auto t0 = std::chrono::steady_clock::now();
    fn();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// One benchmarked case: a Glint filter and, when there is one, its OpenCV peer.
struct Case {
    std::string key;
    std::function<void()> glint;
    std::string peerKey;
    std::function<void()> peer;  // empty: no peer
    int rounds = 0;              // 0: --reps rounds
    std::vector<double> glintSeconds, peerSeconds;
};

double psnr(const Image& a, const Image& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.data().size(); ++i) {
        const double d = double(a.data()[i]) - double(b.data()[i]);
        s += d * d;
    }
    const double mse = s / double(a.data().size());
    return mse > 0.0 ? 10.0 * std::log10(1.0 / mse) : INFINITY;
}

}  // namespace

int main(int argc, char** argv) {
    int threads = 2, size = 1024, reps = 5, curve = 1;
    std::string only;  // run only the cases whose name contains this (and no curve)
    const int parsed = glint::bench::parseOptions(
        "bench_denoise_a", argc, argv, [&](const std::string& a, const std::string& text) {
            if (a == "--only")
                only = text;
            else if (a == "--threads")
                threads = glint::bench::intOption(a, text);
            else if (a == "--size")
                size = glint::bench::intOption(a, text);
            else if (a == "--reps")
                reps = std::max(1, glint::bench::intOption(a, text));
            else if (a == "--curve")
                curve = glint::bench::intOption(a, text);
            else
                return false;
            return true;
        });
    if (parsed != 0) {
        std::fprintf(stderr,
                     "usage: bench_denoise_a [--threads N] [--size N] [--reps N] [--curve 0|1] "
                     "[--only TEXT]\n");
        return parsed;
    }
    if (!only.empty()) curve = 0;  // the curve needs the exact d = 61 reference
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const FrameBuffers frame = testImage(size);
    nlohmann::json report{{"threads", threads}, {"size", size}, {"reps", reps}};
    std::printf("%dx%d RGB float, %d threads, %d interleaved rounds\n", size, size, threads, reps);

    const ParamValues d31{{"sigmaS", 5.0}, {"sigmaR", 0.1}, {"radius", 15}};
    const ParamValues d61{{"sigmaS", 10.0}, {"sigmaR", 0.1}, {"radius", 30}};
    ParamValues mcParams = d61;
    mcParams["samplesPerSide"] = 3;
    Image gauss, exact31, exact61, mc61;
    auto run = [&](const char* name, const ParamValues& p, Image& out) {
        return [&frame, name, p, &out] { out = applyFilter(findFilter(name), frame, p); };
    };
    std::vector<Case> cases;
    cases.push_back(
        {"gaussian sigma=3", run("gaussian", {{"sigma", 3.0}}, gauss), "", {}, 0, {}, {}});
    cases.push_back(
        {"bilateral d=31 sS=5 sR=0.1", run("bilateral", d31, exact31), "", {}, 0, {}, {}});
    cases.push_back({"bilateral-mc d=61 sS=10 k=3 poisson",
                     run("bilateral-mc", mcParams, mc61),
                     "",
                     {},
                     0,
                     {},
                     {}});
    // The exact d = 61 reference is slow: one round.
    cases.push_back(
        {"bilateral d=61 sS=10 sR=0.1 (exact)", run("bilateral", d61, exact61), "", {}, 1, {}, {}});
#ifdef GLINT_BENCH_HAVE_OPENCV
    cv::setNumThreads(threads);
    cv::Mat src(size, size, CV_32FC3, const_cast<float*>(frame.color().data().data()));
    cv::Mat dst;
    cases[0].peerKey = "GaussianBlur sigma=3 19x19";
    cases[0].peer = [&] { cv::GaussianBlur(src, dst, cv::Size(19, 19), 3.0); };
    cases[1].peerKey = "bilateralFilter d=31 sS=5";
    cases[1].peer = [&] { cv::bilateralFilter(src, dst, 31, 0.1, 5.0); };
    cases[3].peerKey = "bilateralFilter d=61 sS=10";
    cases[3].peer = [&] { cv::bilateralFilter(src, dst, 61, 0.1, 10.0); };
#else
    std::printf("  (OpenCV not found at configure time: no side-by-side figures)\n");
#endif
    if (!only.empty())
        std::erase_if(cases, [&](const Case& c) { return c.key.find(only) == std::string::npos; });
    // Interleave: round r runs every case's Glint filter and then its peer.
    for (int r = 0; r < reps; ++r)
        for (Case& c : cases) {
            if (c.rounds > 0 && r >= c.rounds) continue;
            c.glintSeconds.push_back(secondsOf(c.glint));
            if (c.peer) c.peerSeconds.push_back(secondsOf(c.peer));
        }
    std::printf("  %-36s %9s %9s | %-27s %9s %9s | %s\n", "case", "median s", "min s",
                "OpenCV peer", "median s", "min s", "median Glint/OpenCV");
    for (const Case& c : cases) {
        const double gMed = median(c.glintSeconds);
        const double gMin = *std::min_element(c.glintSeconds.begin(), c.glintSeconds.end());
        report["seconds"][c.key] = gMed;
        report["secondsMin"][c.key] = gMin;
        report["secondsAll"][c.key] = c.glintSeconds;
        std::printf("  %-36s %9.4f %9.4f |", c.key.c_str(), gMed, gMin);
        if (c.peer) {
            std::vector<double> ratio;
            for (std::size_t i = 0; i < c.glintSeconds.size(); ++i)
                ratio.push_back(c.glintSeconds[i] / c.peerSeconds[i]);
            const double pMed = median(c.peerSeconds);
            const double pMin = *std::min_element(c.peerSeconds.begin(), c.peerSeconds.end());
            report["opencvSeconds"][c.peerKey] = pMed;
            report["opencvSecondsMin"][c.peerKey] = pMin;
            report["opencvSecondsAll"][c.peerKey] = c.peerSeconds;
            report["ratioToOpencv"][c.key] = median(ratio);
            std::printf(" %-27s %9.4f %9.4f | %.3f\n", c.peerKey.c_str(), pMed, pMin,
                        median(ratio));
        } else {
            std::printf("\n");
        }
    }
    if (!mc61.empty() && !exact61.empty()) {
        report["psnrMcVsExactD61"] = psnr(mc61, exact61);
        std::printf("  PSNR bilateral-mc d=61 vs exact: %.2f dB\n", psnr(mc61, exact61));
    }
    if (!curve) {
        std::printf("%s\n", report.dump().c_str());
        return 0;
    }

    // Accuracy versus samples (Banterle et al. 2012, Fig. 4 style): PSNR against the exact
    // d = 61 bilateral for k N samples, k = 1..7, N = 61.
    const char* kinds[] = {"poisson", "regular", "random", "stratified"};
    std::printf("\n  bilateral-mc d=61 PSNR (dB) vs exact, time (s)\n  k  samples");
    for (const char* k : kinds) std::printf(" %17s", k);
    std::printf("\n");
    for (int k = 1; k <= 7; ++k) {
        std::printf("  %d  %7d", k, k * 61);
        for (int kind = 0; kind < 4; ++kind) {
            ParamValues p = d61;
            p["samplesPerSide"] = k;
            p["pattern"] = kind;
            Image out;
            const double t =
                secondsOf([&] { out = applyFilter(findFilter("bilateral-mc"), frame, p); });
            const double q = psnr(out, exact61);
            report["curve"][kinds[kind]].push_back({{"k", k}, {"psnr", q}, {"seconds", t}});
            std::printf("    %6.2f  %6.3f", q, t);
        }
        std::printf("\n");
    }
    std::printf("%s\n", report.dump().c_str());
    return 0;
}
