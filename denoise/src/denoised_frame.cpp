#include "glint/denoise/denoised_frame.h"

#include "glint/image/composite.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {
constexpr const char* kFilterKey = "denoiseFilter";
constexpr const char* kSessionKey = "denoiseSession";
}  // namespace

bool colourIsDenoised(const FrameBuffers& frame) {
    const auto& extra = frame.metadata().extra;
    return extra.count(kFilterKey) > 0 || extra.count(kSessionKey) > 0 || frame.has(Layer::Noisy);
}

std::string denoisedMark(const FrameBuffers& frame) {
    const auto& extra = frame.metadata().extra;
    for (const char* key : {kFilterKey, kSessionKey})
        if (const auto it = extra.find(key); it != extra.end())
            return std::string(key) + ": " + it->second;
    return frame.has(Layer::Noisy) ? "layer noisy" : std::string();
}

bool keepsRender(const FrameBuffers& frame) {
    return frame.has(Layer::Noisy);
}

FrameBuffers denoisedFrame(const FrameBuffers& render, const Image& colour, int x0, int y0,
                           std::string_view filter, const Image* outside) {
    // The colour around the region: the file's shown colour, else the render's; copied once.
    const Image& around = outside ? *outside : render.color();
    if (!around.sameShape(render.color()))
        throw Error(ErrorKind::InvalidArgument,
                    "the colour around the region is not the frame's size", {}, "denoisedFrame");
    Image shown = around;
    paste(shown, colour, x0, y0);
    FrameBuffers out = render.sharedCopy();
    out.set(Layer::Color, std::move(shown));
    // A render's colour becomes the noisy layer; a denoised input keeps the noisy layer it has (the
    // render), or has none left to keep.
    if (!colourIsDenoised(render)) out.shareLayer(Layer::Noisy, render, Layer::Color);
    out.metadata().extra[kFilterKey] = std::string(filter);
    return out;
}

FrameBuffers renderOf(const FrameBuffers& frame) {
    FrameBuffers out = frame.sharedCopy();
    if (!keepsRender(frame)) return out;
    out.shareLayer(Layer::Color, frame, Layer::Noisy);
    out.metadata().colorReadFrom = Layer::Noisy;  // errors about the colour name the noisy layer
    out.remove(Layer::Noisy);
    out.metadata().extra.erase(kFilterKey);
    out.metadata().extra.erase(kSessionKey);
    return out;
}

std::string renderOfNote(const FrameBuffers& frame, const std::string& file) {
    if (!keepsRender(frame)) return {};
    const auto& extra = frame.metadata().extra;
    const auto by = extra.find(kFilterKey);
    return file + " keeps its render (layer noisy): denoising that, not its colour" +
           (by != extra.end() ? " (denoised by " + by->second + ")" : std::string()) + "\n";
}

}  // namespace glint::denoise
