// FLIP benchmark (docs/lab/flip.md): times glint::flip, LDR and HDR, on two deterministic RGB
// images and prints one JSON object. Goal of issue 50: at most 1 s at 1024x1024 on 2 threads.
//
//   build/bin/bench_flip [--size 1024] [--repeat 5]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/flip.h"

namespace {

[[noreturn]] void usage(const std::string& problem) {
    std::cerr << "bench_flip: " << problem << "\nusage: bench_flip [--size N>=8] [--repeat R>=1]\n";
    std::exit(2);
}

/// A smooth radiance with hard edges and a few bright spots, and a noisy copy (relative Gaussian
/// noise of 20 %, seed 7). LDR uses both clamped to [0, 1].
void makeImages(int size, glint::Image& image, glint::Image& reference) {
    reference = glint::Image(size, size, 3);
    image = glint::Image(size, size, 3);
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.2f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) {
                const double smooth =
                    0.45 + 0.3 * std::sin(0.02 * (c + 1) * x) * std::cos(0.015 * y + c);
                const double checker = ((x / 64 + y / 64) % 2) ? 0.15 : 0.0;
                const double spot = (x % 128 < 4 && y % 128 < 4) ? 20.0 : 0.0;
                const float r = float(smooth + checker + spot);
                reference(x, y, c) = r;
                image(x, y, c) = std::max(0.0f, r * (1.0f + noise(rng)));
            }
}

nlohmann::json timeIt(int repeat, const std::function<void()>& f) {
    f();
    std::vector<double> ms;
    for (int i = 0; i < repeat; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                .count());
    }
    std::sort(ms.begin(), ms.end());
    return {{"median", ms[ms.size() / 2]}, {"min", ms.front()}};
}

}  // namespace

int main(int argc, char** argv) {
    int size = 1024, repeat = 5;
    for (int i = 1; i < argc; i += 2) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) usage("missing value after " + flag);
        const int v = std::atoi(argv[i + 1]);
        if (flag == "--size" && v >= 8 && v <= 16384)
            size = v;
        else if (flag == "--repeat" && v >= 1)
            repeat = v;
        else
            usage("bad option " + flag + " " + argv[i + 1]);
    }
    try {
        glint::Image image, reference;
        makeImages(size, image, reference);
        glint::Image ldrImage = image, ldrReference = reference;
        for (float& v : ldrImage.data()) v = std::min(v, 1.0f);
        for (float& v : ldrReference.data()) v = std::min(v, 1.0f);
        glint::FlipOptions ldr, hdr;
        hdr.hdr = true;
        nlohmann::json out = {{"width", size}, {"height", size}, {"repeat", repeat}};
        glint::FlipResult ldrResult, hdrResult;
        out["ms"]["ldr"] =
            timeIt(repeat, [&] { ldrResult = glint::flip(ldrImage, ldrReference, ldr); });
        out["ms"]["hdr"] = timeIt(repeat, [&] { hdrResult = glint::flip(image, reference, hdr); });
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            out["ms"]["ldr_1thread"] =
                timeIt(repeat, [&] { (void)glint::flip(ldrImage, ldrReference, ldr); });
        }
        out["flip_ldr"] = ldrResult.mean;
        out["flip_hdr"] = hdrResult.mean;
        out["hdr_exposures"] = hdrResult.exposures;
        std::cout << out.dump() << "\n";
    } catch (const glint::Error& e) {
        std::cerr << "bench_flip: " << e.what() << "\n";
        return 1;
    }
}
