#include "film/continued_frame.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "glint/image/error.h"
#include "glint/render/settings_codec.h"

namespace glint::render {

int checkContinuedFrame(const FrameBuffers& frame, const Settings& settings, int width, int height,
                        int startSpp, bool keepsHalf) {
    auto bad = [](const std::string& what, const std::string& where = "continueFrom") {
        throw Error(ErrorKind::InvalidArgument, "cannot go on from this frame: " + what, {}, where);
    };
    auto name = [](Layer layer) {
        const std::string_view n = layerInfo(layer).name;
        return n.empty() ? std::string("colour") : std::string(n);
    };
    const FrameMetadata& meta = frame.metadata();
    if (frame.width() != width || frame.height() != height)
        bad("it is " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
            ", the scene renders " + std::to_string(width) + "x" + std::to_string(height));
    if (meta.integrator != "path")
        bad("expected a path-traced render, got integrator '" + meta.integrator + "'");
    if (meta.seed != settings.seed)
        bad("it was rendered with seed " + std::to_string(meta.seed) + ", this render has seed " +
            std::to_string(settings.seed) + " (expected the same sample sequences)");
    // What makes a sample what it is: the settings the frame records against this render's.
    FrameMetadata mine;
    recordSettings(settings, mine);
    for (const char* key : {"sampler", "mis", "strategy", "maxDepth", "rrDepth", "halfBuffers"}) {
        const auto want = mine.extra.find(key);
        if (want == mine.extra.end()) continue;  // strategy without mis none
        const auto got = meta.extra.find(key);
        if (got == meta.extra.end() || got->second != want->second)
            bad(std::string("it was rendered with ") + key + " " +
                (got == meta.extra.end() ? "unrecorded" : "'" + got->second + "'") +
                ", this render has '" + want->second + "' (expected the same)");
    }
    if (meta.nonFiniteSamples != 0)
        bad("it discarded " + std::to_string(meta.nonFiniteSamples) +
            " non-finite samples, so its pixels' counts are not their next sample indices "
            "(expected none discarded)");
    const bool halves = settings.halfBuffers || keepsHalf;
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        const bool needed = layer != Layer::Noisy &&
                            (layer != Layer::Position || settings.positionLayer) &&
                            (!isHalfLayer(layer) || halves);
        if (needed && !frame.has(layer))
            bad("it has no " + name(layer) + " layer (expected every layer the film is made of" +
                (isHalfLayer(layer) ? std::string(", half buffers included") : std::string()) +
                ")");
    }
    const int most = settings.spp > 0 ? settings.spp : kMaxSpp;
    int largest = 0;
    auto at = [](int x, int y) {
        return "continueFrom/pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")";
    };
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float n = frame.layer(Layer::SampleCount)(x, y, 0);
            if (!(n >= float(startSpp) && n <= float(most) && n == std::floor(n)))
                bad("sample count " + numberText(n) + "; expected a whole number in [" +
                        std::to_string(startSpp) + ", " + std::to_string(most) +
                        "] (the adaptive start to spp)",
                    at(x, y));
            if (halves && frame.layer(Layer::HalfSampleCount)(x, y, 0) != std::floor(n / 2.0f))
                bad("half B's sample count " +
                        numberText(frame.layer(Layer::HalfSampleCount)(x, y, 0)) +
                        "; expected half of the pixel's " + numberText(n) + " (its odd samples)",
                    at(x, y));
            largest = std::max(largest, int(n));
            for (int l = 0; l < kLayerCount; ++l) {
                const Layer layer = Layer(l);
                if (layer == Layer::Noisy || !frame.has(layer)) continue;
                const Image& image = frame.layer(layer);
                for (int c = 0; c < image.channels(); ++c)
                    if (!std::isfinite(image(x, y, c)))
                        bad(name(layer) + " is " + numberText(image(x, y, c)) +
                                "; expected a finite value",
                            at(x, y));
            }
        }
    return largest;
}

}  // namespace glint::render
