// Image assertions for test suites (docs/testing.md): expectations such as "ssim>=0.98",
// "flip<=0.05" or "mc" checked against a reference, as `glint-image diff --expect` and
// glint/image/testing.h do.
#pragma once

#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/metrics.h"

namespace glint {

/// One expectation, parsed from text.
struct Expectation {
    std::string text;  ///< as given
    /// "mc": the Monte Carlo-aware comparison of glint/image/mc_compare.h.
    bool monteCarlo = false;
    /// Metric expectations: the metric ("flip" resolves per input, see ComparedImage::hdr).
    std::string metric;
    bool atLeast = true;     ///< >= (or >) when true, <= (or <) otherwise
    bool strict = false;     ///< > or <
    double threshold = 0.0;  ///< bound, or for "mc" the false-alarm rate
};

/// Parses "METRIC>=X", "METRIC<=X" (also > and <) with METRIC one of ssim, psnr, mse, relmse,
/// flip, flip-ldr, flip-hdr, or "mc" / "mc:ALPHA" (false-alarm rate, default 1e-4). Throws
/// glint::Error(InvalidArgument) naming what is accepted.
Expectation parseExpectation(const std::string& text);

/// An image to compare, as read from a file.
struct ComparedImage {
    FrameBuffers frame;
    /// Radiance (an EXR): "flip" means HDR-FLIP. Display values (PNG, JPEG...): LDR-FLIP.
    bool hdr = false;
};

/// Reads a layered EXR (hdr) or any other image OpenImageIO reads as a colour-only frame, 8-bit
/// sRGB decoded to linear (not hdr). Throws glint::Error as readExr / readImage do.
ComparedImage readComparedImage(const std::string& path);

/// The metric an expectation or `--metric flip` names for these inputs.
Metric resolveMetric(const std::string& name, bool hdr);

/// What came of one expectation.
struct ExpectationOutcome {
    Expectation expectation;
    bool passed = false;
    double value = 0.0;   ///< the metric, or for "mc" the worst window's statistic
    std::string message;  ///< one line: what was found, and by how much it missed
};

/// Checks every expectation of `image` against `reference` (colour layers; "mc" also needs both
/// variance layers). `options` (crop, SSIM's display settings) apply to metric expectations;
/// "mc" compares the whole image. Throws glint::Error for bad input (shapes, NaN for FLIP, an LDR
/// metric on HDR values, missing variance layers); a failed expectation is an outcome, not an
/// error.
std::vector<ExpectationOutcome> checkExpectations(const ComparedImage& image,
                                                  const ComparedImage& reference,
                                                  const std::vector<Expectation>& expectations,
                                                  const MetricOptions& options = {});

}  // namespace glint
