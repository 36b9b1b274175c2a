// Whether a render can go on from a finished one (Settings::continueFrom): the frame's settings,
// size, layers and per-pixel statistics against the render's.
#pragma once

#include "glint/image/frame_buffers.h"
#include "glint/render/settings.h"

namespace glint::render {

/// Throws glint::Error(InvalidArgument, where "continueFrom…") unless a `width` × `height` render
/// of `settings`, whose adaptive passes begin at `startSpp` samples a pixel, can go on from
/// `frame`: a path-traced render with the same seed, sampler, MIS, depths and half buffers, of
/// the film's size, with the layers the film is made of (half B's when `keepsHalf`, the position
/// when the render writes it), no sample discarded, and per pixel finite statistics, a whole
/// count in [startSpp, spp] (spp 0: any) and half B's count half of it. Returns the largest
/// count: where the render's own count of samples a pixel goes on.
int checkContinuedFrame(const FrameBuffers& frame, const Settings& settings, int width, int height,
                        int startSpp, bool keepsHalf);

}  // namespace glint::render
