// bench_unet: the speed and memory figures of the learned filter "unet" in docs/learned.md.
// Renders cornell at size² (albedo and normal; not timed), or with --width/--height makes a
// synthetic frame of that size (colour, albedo, normal only: for the memory figure under
// /usr/bin/time -v), then times unet with its default weights on `threads` threads, best of
// `reps`. Also times one oneDNN convolution alone (64 → 64 channels, 3×3, on a 512² tile, the
// library's best case in this network) so that the filter's throughput can be stated as a
// fraction of oneDNN's own. Prints one JSON object.
//   build/bin/bench_unet [--size 1024] [--spp 16] [--threads 2] [--reps 3] [--quality 1]
//   build/bin/bench_unet --width 3840 --height 2160 --reps 1       (under /usr/bin/time -v)
#include <omp.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <oneapi/dnnl/dnnl.hpp>
#include <random>
#include <string>

#include "bench_options.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"
#include "learned/tza.h"
#include "learned/unet_network.h"

namespace {

// Seconds of the fastest of `reps` calls of fn.
template <typename Fn>
double best(int reps, Fn&& fn) {
    double t = std::numeric_limits<double>::infinity();
    for (int r = 0; r < reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        t = std::min(t,
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return t;
}

// GFLOP/s of one 3×3 convolution c → c on a side² tile, formats chosen by oneDNN, ReLU fused.
double convGflops(int c, int side, int threads, int reps) {
    using dnnl::memory;
    const dnnl::engine eng(dnnl::engine::kind::cpu, 0);
    dnnl::stream s(eng);
    const memory::desc any({1, c, side, side}, memory::data_type::f32, memory::format_tag::any);
    const memory::desc w({c, c, 3, 3}, memory::data_type::f32, memory::format_tag::any);
    const memory::desc b({c}, memory::data_type::f32, memory::format_tag::x);
    dnnl::post_ops po;
    po.append_eltwise(1.0f, dnnl::algorithm::eltwise_relu, 0.0f, 0.0f);
    dnnl::primitive_attr attr;
    attr.set_post_ops(po);
    const dnnl::convolution_forward::primitive_desc pd({dnnl::prop_kind::forward_inference,
                                                        dnnl::algorithm::convolution_direct,
                                                        any,
                                                        w,
                                                        b,
                                                        any,
                                                        {1, 1},
                                                        {1, 1},
                                                        {1, 1}},
                                                       attr, eng);
    memory src(pd.src_desc(), eng), wei(pd.weights_desc(), eng), bias(b, eng),
        dst(pd.dst_desc(), eng);
    for (auto* m : {&src, &wei, &bias}) {
        float* p = static_cast<float*>(m->get_data_handle());
        for (std::size_t i = 0; i < m->get_desc().get_size() / 4; ++i) p[i] = float(i % 7) * 0.01f;
    }
    omp_set_num_threads(threads);
    const dnnl::convolution_forward conv(pd);
    auto run = [&] {
        conv.execute(s, {{DNNL_ARG_SRC, src},
                         {DNNL_ARG_WEIGHTS, wei},
                         {DNNL_ARG_BIAS, bias},
                         {DNNL_ARG_DST, dst}});
        s.wait();
    };
    run();  // warm-up
    const double t = best(std::max(reps, 3), run);
    return 2.0 * c * c * 9.0 * side * side / t * 1e-9;
}

// Colour, albedo and normal of w × h with noise (fixed seed): the memory figure's input.
glint::FrameBuffers syntheticFrame(int w, int h) {
    glint::FrameBuffers f(w, h);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    glint::Image& c = f.color();
    glint::Image& a = f.ensure(glint::Layer::Albedo);
    glint::Image& n = f.ensure(glint::Layer::Normal);
    for (std::size_t i = 0; i < c.data().size(); ++i) {
        c.data()[i] = u(rng);
        a.data()[i] = 0.5f;
        n.data()[i] = i % 3 == 2 ? 1.0f : 0.0f;
    }
    return f;
}

}  // namespace

int main(int argc, char** argv) {
    namespace fs = std::filesystem;
    int size = 1024, spp = 16, threads = 2, reps = 3, quality = 1, width = 0, height = 0;
    const int parsed = glint::bench::parseOptions(
        "bench_unet", argc, argv, [&](const std::string& a, const std::string& text) {
            const int v = glint::bench::intOption(a, text);
            for (auto [name, slot] : {std::pair{"--size", &size},
                                      {"--spp", &spp},
                                      {"--threads", &threads},
                                      {"--reps", &reps},
                                      {"--quality", &quality},
                                      {"--width", &width},
                                      {"--height", &height}})
                if (a == name) {
                    *slot = v;
                    return true;
                }
            return false;
        });
    if (parsed != 0) return parsed;
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, std::size_t(threads));
    const fs::path root = GLINT_SOURCE_DIR;

    glint::FrameBuffers frame;
    if (width > 0 && height > 0) {
        frame = syntheticFrame(width, height);
    } else {
        // The input: cornell at size², spp samples (the render is not timed).
        std::ifstream in(root / "scenes/cornell/scene.json");
        nlohmann::json scene = nlohmann::json::parse(in);
        scene["film"] = {{"width", size}, {"height", size}};
        glint::render::Renderer renderer(
            glint::render::parseScene(scene.dump(), root / "scenes/cornell/scene.json"));
        glint::render::Settings s = renderer.scene().settings();
        s.spp = spp;
        s.threads = threads;
        frame = renderer.render(s).frame;
    }

    const glint::denoise::Filter& filter = glint::denoise::findFilter("unet");
    glint::denoise::FilterOptions options;
    options.threads = threads;
    const glint::denoise::ParamValues params{{"quality", quality}};
    const double seconds =
        best(reps, [&] { glint::denoise::applyFilter(filter, frame, params, options); });

    // FLOPs of the weights used (albedo + normal at this quality).
    const std::string weights = quality == 0 ? "rt_hdr_alb_nrm_small" : "rt_hdr_alb_nrm";
    const fs::path file = root / "denoise/weights/oidn" / (weights + ".tza");
    std::ifstream wf(file, std::ios::binary);
    const std::vector<std::uint8_t> blob{std::istreambuf_iterator<char>(wf),
                                         std::istreambuf_iterator<char>()};
    const glint::denoise::learned::UNetNetwork net(
        glint::denoise::learned::parseTza(blob, file.string()), 9, file.string());
    const double pixels = double(frame.width()) * frame.height();
    const double flopsPerPixel = 2.0 * net.macsPerPixel();
    const double filterGflops = flopsPerPixel * pixels / seconds * 1e-9;
    const double convPeak = convGflops(64, 512, threads, reps);

    const nlohmann::json out = {{"width", frame.width()},
                                {"height", frame.height()},
                                {"threads", threads},
                                {"reps", reps},
                                {"weights", weights},
                                {"seconds", seconds},
                                {"flopsPerPixel", flopsPerPixel},
                                {"filterGflops", filterGflops},
                                {"onednnConv64Gflops", convPeak},
                                {"fractionOfOnednnConv", filterGflops / convPeak},
                                {"activationBytesPerPixel", net.bytesPerPixel()}};
    std::printf("%s\n", out.dump(2).c_str());
    return 0;
}
