// A denoised frame and the render it came from (docs/image.md, "The noisy layer"): a denoiser's
// output keeps the render's colour as its noisy layer, as Blender keeps Cycles' "Noisy Image",
// so the file can be denoised again from the render and nothing the render made is lost.
#pragma once

#include <string>
#include <string_view>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// Whether `frame`'s colour is already denoised: its metadata names a denoiseFilter (glint-final's
/// and glint-denoise's outputs) or a denoiseSession (the studio's export), or it has a noisy layer
/// (a Cycles file with denoising on). Its variance and half buffers are the render's, which do not
/// describe that colour.
bool colourIsDenoised(const FrameBuffers& frame);

/// What marks `frame` as denoised, for messages: "denoiseFilter: auto", "denoiseSession: 2 layers"
/// or "layer noisy"; empty when colourIsDenoised is false.
std::string denoisedMark(const FrameBuffers& frame);

/// Whether `frame` is denoised and keeps the render's colour in its noisy layer (renderOf can
/// give the render back).
bool keepsRender(const FrameBuffers& frame);

/// The frame a denoiser writes: `render`'s layers (shared, not copied), its colour `colour` pasted
/// at (x0, y0) over `outside` where given (the colour a denoised file showed around the region
/// denoised again), else over the render's colour; the render's colour kept as the noisy layer, and
/// metadata denoiseFilter = `filter`. An input already denoised keeps the noisy layer it has (an
/// older file without one has no render left to keep). Throws glint::Error(InvalidArgument) when
/// `colour` does not fit or `outside` is not the frame's size.
FrameBuffers denoisedFrame(const FrameBuffers& render, const Image& colour, int x0, int y0,
                           std::string_view filter, const Image* outside = nullptr);

/// The render `frame` holds: `frame` itself (shared) unless it keepsRender, else the frame with its
/// noisy layer as the colour, no noisy layer and no denoiseFilter / denoiseSession metadata, so
/// every estimator and filter sees the render the statistics describe.
FrameBuffers renderOf(const FrameBuffers& frame);

/// The one line a command prints when it denoises the render kept in `file` (keepsRender) rather
/// than the file's colour; empty when `frame` does not keep one.
std::string renderOfNote(const FrameBuffers& frame, const std::string& file);

}  // namespace glint::denoise
