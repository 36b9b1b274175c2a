// Putting images together: paste a region's result back into a frame, blend two images by a
// per-pixel weight. The filter CLI, the painting session and the studio all use these.
#pragma once

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint {

/// Copies `src` into `dst` with its top-left pixel at (x0, y0). The channel counts must match
/// and `src` must lie inside `dst`; throws glint::Error(InvalidArgument) otherwise.
void paste(Image& dst, const Image& src, int x0, int y0);
/// `frame` with `src` pasted over its colour at (x0, y0) (paste): a denoiser's output frame. Only
/// the colour is copied; the other layers are shared with `frame` (FrameBuffers::sharedCopy).
FrameBuffers withColorPasted(const FrameBuffers& frame, const Image& src, int x0, int y0);

/// Per-pixel linear blend a·(1 − w) + b·w. `a` and `b` have the same shape, `weight` their size
/// and one channel (or their channel count: one weight per channel). Weights are clamped to
/// [0, 1]; where w is exactly 0 the result is `a` bit for bit, where it is 1 it is `b` (so a
/// non-finite value in the image with no weight does not leak through). Throws
/// glint::Error(InvalidArgument) for mismatched shapes.
Image blend(const Image& a, const Image& b, const Image& weight);

/// In-place form of blend() over `rect` only: dst = dst·(1 − w) + src·w for the pixels of
/// `rect`, where `src` and `weight` cover the whole of dst (same size). Used for brush dabs.
void blendInPlace(Image& dst, const Image& src, const Image& weight, const Rect& rect);

}  // namespace glint
