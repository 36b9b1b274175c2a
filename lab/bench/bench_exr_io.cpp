// EXR write + read of a 1024x1024 frame with every layer (goal: under 300 ms per round trip),
// beside the peer: OpenImageIO reading the same file (its OpenEXRCore reader, as Glint used it
// until 2026-12-03) and writing it from one interleaved buffer.
// Run: build/bin/bench_exr_io [--benchmark_repetitions=5]
#include <OpenImageIO/imageio.h>
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"

namespace {

/// A frame with all ten layers filled with render-like noise (deterministic; no compression
/// advantage from constant data).
glint::FrameBuffers makeFrame(int size) {
    glint::FrameBuffers frame(size, size);
    std::uint32_t state = 12345u;
    for (int l = 0; l < glint::kLayerCount; ++l) {
        if (glint::Layer(l) == glint::Layer::Noisy)
            continue;  // a render's layers: not a denoiser's
        glint::Image& im = frame.ensure(glint::Layer(l));
        for (float& v : im.data()) {
            state = state * 1664525u + 1013904223u;  // LCG; only the values' spread matters
            v = float(l) + float(state >> 8) * (1.0f / 16777216.0f);
        }
    }
    frame.metadata().spp = 16;
    frame.metadata().integrator = "path";
    return frame;
}

std::filesystem::path benchPath(const char* name) {
    return std::filesystem::temp_directory_path() /
           ("glint_bench_" + std::to_string(::getpid()) + "_" + name);
}

void BM_ExrWriteRead(benchmark::State& state) {
    const glint::FrameBuffers frame = makeFrame(int(state.range(0)));
    const auto file = benchPath("roundtrip.exr");
    for (auto _ : state) {
        glint::writeExr(frame, file);
        glint::FrameBuffers back = glint::readExr(file);
        benchmark::DoNotOptimize(back.color().data().data());
    }
    state.counters["MB"] = double(std::filesystem::file_size(file)) / 1e6;
    std::filesystem::remove(file);
}

void BM_ExrWrite(benchmark::State& state) {
    const glint::FrameBuffers frame = makeFrame(int(state.range(0)));
    const auto file = benchPath("write.exr");
    for (auto _ : state) glint::writeExr(frame, file);
    std::filesystem::remove(file);
}

void BM_ExrRead(benchmark::State& state) {
    const auto file = benchPath("read.exr");
    glint::writeExr(makeFrame(int(state.range(0))), file);
    for (auto _ : state) {
        glint::FrameBuffers back = glint::readExr(file);
        benchmark::DoNotOptimize(back.color().data().data());
    }
    std::filesystem::remove(file);
}

void BM_OpenImageIoRead(benchmark::State& state) {
    const auto file = benchPath("oiio_read.exr");
    glint::writeExr(makeFrame(int(state.range(0))), file);
    OIIO::attribute("openexr:core", 1);
    std::vector<float> strip;
    for (auto _ : state) {
        // Strips of 32 rows into one buffer, as Glint read through OpenImageIO (it then spread
        // each strip over the layers, which is not counted here).
        auto in = OIIO::ImageInput::open(file.string());
        const OIIO::ImageSpec& spec = in->spec();
        strip.resize(std::size_t(spec.width) * 32 * std::size_t(spec.nchannels));
        for (int y0 = 0; y0 < spec.height; y0 += 32)
            if (!in->read_scanlines(0, 0, y0, std::min(spec.height, y0 + 32), 0, 0, spec.nchannels,
                                    OIIO::TypeFloat, strip.data()))
                state.SkipWithError("OpenImageIO could not read the frame");
        benchmark::DoNotOptimize(strip.data());
    }
    std::filesystem::remove(file);
}

void BM_OpenImageIoWrite(benchmark::State& state) {
    const auto file = benchPath("oiio_write.exr");
    const auto read = benchPath("oiio_source.exr");
    glint::writeExr(makeFrame(int(state.range(0))), read);
    auto in = OIIO::ImageInput::open(read.string());
    OIIO::ImageSpec spec = in->spec();
    std::vector<float> pixels(spec.image_pixels() * std::size_t(spec.nchannels));
    in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, pixels.data());
    in->close();
    spec.attribute("compression", "none");
    for (auto _ : state) {
        auto out = OIIO::ImageOutput::create(file.string());
        if (!out->open(file.string(), spec) || !out->write_image(OIIO::TypeFloat, pixels.data()))
            state.SkipWithError("OpenImageIO could not write the frame");
        out->close();
    }
    std::filesystem::remove(file);
    std::filesystem::remove(read);
}

}  // namespace

BENCHMARK(BM_ExrWriteRead)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExrWrite)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_ExrRead)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenImageIoWrite)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_OpenImageIoRead)->Arg(1024)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
