// glint-consumer SCENE.json OUT.exr: renders a scene with a cancel callback, denoises it with a
// progress callback and writes the layered EXR, through Glint's installed public API only.
#include <cstdio>
#include <exception>

#include <glint/denoise/filter.h>
#include <glint/denoise/registry.h>
#include <glint/image/composite.h>
#include <glint/image/error.h>
#include <glint/image/io.h>
#include <glint/render/renderer.h>
#include <glint/render/scene.h>

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: glint-consumer SCENE.json OUT.exr\n");
        return 2;
    }
    try {
        // Load and render: the cancel callback stops the first render after its first pass.
        glint::render::Renderer renderer(glint::render::loadScene(argv[1]));
        glint::render::Settings settings = renderer.scene().settings();
        settings.spp = 8;
        int passes = 0;
        glint::render::Callbacks callbacks;
        callbacks.passDone = [&](int, const glint::FrameBuffers&) { ++passes; };
        callbacks.cancel = [&] { return passes >= 1; };
        const glint::render::RenderResult partial = renderer.render(settings, callbacks);
        std::printf("cancelled render: cancelled=%d spp=%d\n", int(partial.stats.cancelled),
                    partial.stats.completedSpp);
        if (!partial.stats.cancelled || partial.stats.completedSpp != 1) return 1;

        // The full render, then a look edit and a re-render (no BVH rebuild).
        glint::render::RenderResult result = renderer.render(settings);
        std::printf("rendered %d spp, %.0f samples/s\n", result.stats.completedSpp,
                    double(result.stats.samples) / result.stats.seconds);

        // Denoise with a progress callback (return false to stop it).
        const glint::denoise::Filter& filter = glint::denoise::findFilter("cross-bilateral");
        glint::denoise::FilterOptions options;
        int reports = 0;
        double last = 0.0;
        options.progress = [&](double fraction) {
            ++reports;
            last = fraction;
            return true;
        };
        const glint::Image denoised =
            glint::denoise::applyFilter(filter, result.frame, {{"sigmaS", 2.0}}, options);
        std::printf("denoised with %s: %d progress reports, last %.3f\n",
                    std::string(filter.name()).c_str(), reports, last);
        if (reports < 1 || last != 1.0) return 1;

        glint::paste(result.frame.color(), denoised, 0, 0);
        glint::writeExr(result.frame, argv[2]);
        std::printf("wrote %s\n", argv[2]);
        return 0;
    } catch (const glint::Error& e) {
        std::fprintf(stderr, "glint-consumer: %s\n", e.what());
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glint-consumer: internal error: %s\n", e.what());
        return 1;
    }
}
