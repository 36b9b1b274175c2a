// SSIM benchmark: times glint::ssim on two deterministic 1024x1024 RGB images and prints one JSON
// object. With --write-dir it also writes both images as raw float32 (row-major, channels
// interleaved) so lab/bench/ssim_skimage.py can time scikit-image on exactly the same data.
//
//   build/bin/bench_ssim [--size 1024] [--repeat 20] [--write-dir DIR]
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/image.h"
#include "glint/image/metrics.h"

namespace {

struct Args {
    int size = 1024;
    int repeat = 20;
    std::string writeDir;
};

[[noreturn]] void usage(const std::string& problem) {
    std::cerr << "bench_ssim: " << problem
              << "\nusage: bench_ssim [--size N>=11] [--repeat R>=1] [--write-dir DIR]\n";
    std::exit(2);
}

int parsePositive(const std::string& flag, const char* text, int minimum) {
    char* end = nullptr;
    const long v = std::strtol(text, &end, 10);
    if (end == text || *end != '\0' || v < minimum || v > 16384)
        usage(flag + " expects an integer >= " + std::to_string(minimum) + ", got '" + text + "'");
    return int(v);
}

Args parseArgs(int argc, char** argv) {
    Args args;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        if (i + 1 >= argc) usage("missing value after " + flag);
        const char* value = argv[++i];
        if (flag == "--size")
            args.size = parsePositive(flag, value, 11);
        else if (flag == "--repeat")
            args.repeat = parsePositive(flag, value, 1);
        else if (flag == "--write-dir")
            args.writeDir = value;
        else
            usage("unknown option " + flag);
    }
    return args;
}

/// A smooth reference with hard edges (checkerboard) and a copy with Gaussian noise (sigma 0.05,
/// seed 7), both clamped to [0, 1] like display values.
void makeImages(int size, glint::Image& image, glint::Image& reference) {
    reference = glint::Image(size, size, 3);
    image = glint::Image(size, size, 3);
    std::mt19937 rng(7);
    std::normal_distribution<float> noise(0.0f, 0.05f);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x)
            for (int c = 0; c < 3; ++c) {
                const double smooth =
                    0.45 + 0.3 * std::sin(0.02 * (c + 1) * x) * std::cos(0.015 * y + c);
                const double checker = ((x / 64 + y / 64) % 2) ? 0.15 : 0.0;
                const float r = float(std::clamp(smooth + checker, 0.0, 1.0));
                reference(x, y, c) = r;
                image(x, y, c) = std::clamp(r + noise(rng), 0.0f, 1.0f);
            }
}

void writeRaw(const glint::Image& im, const std::filesystem::path& path) {
    const std::filesystem::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary);
        out.write(reinterpret_cast<const char*>(im.data().data()),
                  std::streamsize(im.data().size() * sizeof(float)));
        if (!out) throw glint::Error(glint::ErrorKind::Io, "cannot write", tmp.string());
    }
    std::filesystem::rename(tmp, path);
}

/// Runs f `repeat` times (after one warm-up) and returns {median, min} in milliseconds.
nlohmann::json timeIt(int repeat, const std::function<void()>& f) {
    f();
    std::vector<double> ms;
    for (int i = 0; i < repeat; ++i) {
        const auto t0 = std::chrono::steady_clock::now();
        f();
        const auto t1 = std::chrono::steady_clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return {{"median", ms[ms.size() / 2]}, {"min", ms.front()}};
}

}  // namespace

int main(int argc, char** argv) {
    const Args args = parseArgs(argc, argv);
    try {
        glint::Image image, reference;
        makeImages(args.size, image, reference);
        nlohmann::json out;
        out["width"] = args.size;
        out["height"] = args.size;
        out["channels"] = 3;
        out["repeat"] = args.repeat;

        glint::MetricOptions linear;
        linear.linear = true;
        const glint::MetricOptions display;
        double sLinear = 0.0, sDisplay = 0.0;
        out["ms"]["linear"] =
            timeIt(args.repeat, [&] { sLinear = glint::ssim(image, reference, linear).value; });
        out["ms"]["display"] =
            timeIt(args.repeat, [&] { sDisplay = glint::ssim(image, reference, display).value; });
        out["ms"]["map_linear"] =
            timeIt(args.repeat, [&] { (void)glint::ssimMap(image, reference, linear); });
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            out["ms"]["linear_1thread"] = timeIt(
                std::max(1, args.repeat / 4), [&] { (void)glint::ssim(image, reference, linear); });
            out["ms"]["display_1thread"] = timeIt(std::max(1, args.repeat / 4), [&] {
                (void)glint::ssim(image, reference, display);
            });
        }
        out["ssim_linear"] = sLinear;
        out["ssim_display"] = sDisplay;

        if (!args.writeDir.empty()) {
            const std::filesystem::path dir = args.writeDir;
            std::filesystem::create_directories(dir);
            const std::string shape =
                std::to_string(args.size) + "x" + std::to_string(args.size) + "x3.f32";
            writeRaw(image, dir / ("image_" + shape));
            writeRaw(reference, dir / ("reference_" + shape));
            out["files"] = {{"image", (dir / ("image_" + shape)).string()},
                            {"reference", (dir / ("reference_" + shape)).string()}};
        }
        std::cout << out.dump(2) << "\n";
    } catch (const std::exception& e) {
        std::cerr << "bench_ssim: " << e.what() << "\n";
        return 2;
    }
    return 0;
}
