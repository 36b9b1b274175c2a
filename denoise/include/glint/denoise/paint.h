// Painting primitives of the compositing session: the soft brush, the multi-channel magic wand
// and Poisson-diffusion blending of weight maps (docs/painting.md).
#pragma once

#include <utility>
#include <vector>

#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// A round soft brush (the thesis's Figure 5.4): weight 1 within the inner radius
/// softness·size/2, falling linearly to 0 at the outer radius size/2.
struct Brush {
    double size = 64.0;     ///< diameter in pixels, > 0
    double softness = 0.5;  ///< inner radius / outer radius, in [0, 1]
};

/// Throws glint::Error(InvalidArgument) for a non-finite or non-positive size or a softness
/// outside [0, 1].
void validate(const Brush& brush);

/// Brush weight at `distance` pixels from the dab centre.
float brushWeight(double distance, const Brush& brush);

/// The pixels a dab at (x, y) (pixel centres at half-integers: pixel (i, j) covers
/// [i, i+1) × [j, j+1)) can touch, clipped to a width × height image (may be empty).
Rect dabRect(double x, double y, const Brush& brush, int width, int height);

/// Thresholds of the magic wand: a neighbour joins the region when, for every feature used, its
/// difference to the pixel it is reached from is at most the threshold (the gradient bound).
struct WandOptions {
    /// Colour: |Δ| per channel relative to the larger of the two luminances plus 1e-3 (noise
    /// makes colour gradients large at low spp: < 0 turns the colour test off).
    double color = 0.5;
    double albedo = 0.05;  ///< absolute per channel (< 0: off)
    double normal = 0.1;   ///< absolute per component (< 0: off)
    double depth = 0.02;   ///< relative to the larger of the two depths (< 0: off)
};

/// Flood fill (4-connected) from the pixels where `seeds` (1 channel, frame-sized) is > 0,
/// bounded by the thresholds on each present feature layer (absent layers are not tested).
/// Returns a 0/1 mask of the frame's size. Throws glint::Error(InvalidArgument) for a seed mask
/// of the wrong size.
Image magicWand(const FrameBuffers& frame, const Image& seeds, const WandOptions& options = {});

/// Options of diffuseWeights.
struct DiffusionOptions {
    double tolerance = 1e-6;  ///< relative residual at which the solver stops
    int maxIterations = 500;
};

/// Harmonic interpolation (the steady state of the heat equation): the pixels where `fixed`
/// (1 channel) is > 0 keep their `values` (1 channel, same size); every other pixel gets the
/// value that satisfies the discrete Laplace equation (5-point stencil; mirror, i.e. zero-flux,
/// borders). Solved by multigrid-preconditioned conjugate gradients. Throws
/// glint::Error(InvalidArgument) when no pixel is fixed or the sizes differ, Error(Numeric) if
/// it does not converge, Error(Cancelled) when progress says stop.
Image diffuseWeights(const Image& values, const Image& fixed, const DiffusionOptions& options = {},
                     const ProgressFn& progress = {});

}  // namespace glint::denoise
