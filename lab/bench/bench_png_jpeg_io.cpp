// Reading a texture-sized PNG and JPEG (2048², RGBA and RGB, 8-bit, render-like content) as
// glint::readImage reads them — libpng and libjpeg-turbo, then sRGB decoded to linear float —
// beside the peer: OpenImageIO reading the same file to float in the same process, then the
// same decode (by the same 256-entry table). Neither figure includes loading OpenImageIO (the
// peer's is loaded before the first run); what a process saves by not loading it is
// docs/research/start-and-writing.md's.
// Run: build/bin/bench_png_jpeg_io [--benchmark_repetitions=5]
#include <OpenImageIO/imageio.h>
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include "glint/image/io.h"

namespace {

constexpr int kSize = 2048;

std::filesystem::path benchPath(const char* name) {
    return std::filesystem::temp_directory_path() /
           ("glint_bench_" + std::to_string(::getpid()) + "_" + name);
}

/// A smooth pattern with grain, so that compression does what it does on a photographed
/// texture; written once per process.
const std::filesystem::path& file(const char* name, int channels) {
    static std::filesystem::path paths[2];
    std::filesystem::path& path = paths[channels == 4 ? 0 : 1];
    if (path.empty()) {
        glint::Image im(kSize, kSize, channels);
        std::uint32_t state = 777u;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                for (int c = 0; c < channels; ++c) {
                    state = state * 1664525u + 1013904223u;
                    const float grain = float(state >> 8) * (1.0f / 16777216.0f) - 0.5f;
                    const float base = 0.5f + 0.3f * std::sin(0.01f * float(x * (c + 1))) *
                                                  std::cos(0.013f * float(y));
                    im(x, y, c) = c == 3 ? 1.0f : std::fmax(0.0f, base + 0.05f * grain);
                }
        path = benchPath(name);
        glint::writeImage(im, path);
    }
    return path;
}

void readByGlint(benchmark::State& state, const std::filesystem::path& path) {
    for (auto _ : state) benchmark::DoNotOptimize(glint::readImage(path, true));
}

void readByOpenImageIo(benchmark::State& state, const std::filesystem::path& path) {
    float table[256];
    for (int i = 0; i < 256; ++i) table[i] = glint::srgbDecode(float(i) * (1.0f / 255.0f));
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    for (auto _ : state) {
        auto in = OIIO::ImageInput::open(path.string(), &config);
        const OIIO::ImageSpec& spec = in->spec();
        glint::Image im(spec.width, spec.height, spec.nchannels);
        in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, im.data().data());
        for (std::size_t i = 0; i < im.data().size(); ++i)
            if (int(i % std::size_t(spec.nchannels)) != spec.alpha_channel)
                im.data()[i] = table[std::lround(im.data()[i] * 255.0f)];
        benchmark::DoNotOptimize(im);
    }
}

void BM_PngRead(benchmark::State& state) {
    readByGlint(state, file("t.png", 4));
}
void BM_OpenImageIoPngRead(benchmark::State& state) {
    readByOpenImageIo(state, file("t.png", 4));
}
void BM_JpegRead(benchmark::State& state) {
    readByGlint(state, file("t.jpg", 3));
}
void BM_OpenImageIoJpegRead(benchmark::State& state) {
    readByOpenImageIo(state, file("t.jpg", 3));
}

}  // namespace

BENCHMARK(BM_PngRead)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenImageIoPngRead)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_JpegRead)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenImageIoJpegRead)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    std::error_code ignored;
    for (const char* name : {"t.png", "t.jpg"}) std::filesystem::remove(benchPath(name), ignored);
    return 0;
}
