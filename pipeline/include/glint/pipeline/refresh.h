// The steering loop's refresh: auto on the frame so far with its per-pixel error of the denoised
// image (autoRun, denoiseFrame: what glint-final's loop, final_render.h, runs too), and for the
// studio's progressive render (docs/studio.md, "Keep refining") the Refresher, which runs it again
// whenever the mean samples per pixel have grown by a factor and makes the importance map the
// renderer's Callbacks::importance returns for the next adaptive passes. glint-final schedules its
// refreshes itself, under its time budget (time_budget.h).
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::pipeline {

/// What a refresh runs and how its map is made.
struct RefreshOptions {
    /// Run auto again once the mean samples per pixel have grown by this factor (> 1).
    double growth = 2.0;
    /// The automatic selection (AutoOptions::estimateError is set here); its tuning, when
    /// empty, is the quality's.
    denoise::AutoOptions autoOptions;
    denoise::AutoQuality quality = denoise::AutoQuality::Balanced;
    /// The bank's Latin-hypercube members (0: the quality's) and filters (empty: the default
    /// bank's). The studio keeps its refreshes cheap with a few of one or two filters.
    int bankSize = 0;
    std::vector<std::string> filters;
    /// The variance-only map: the schedule's scale everywhere (auto still runs, for the target).
    bool varianceOnly = false;
    /// The fraction of the pixels the map keeps open, the worst by auto's relative error (the
    /// others weigh 0: they keep their samples until a later refresh names them); 1: all. Short
    /// adaptive passes for a display that refreshes often.
    double focus = 1.0;
    /// The threads auto may take: 0, those of the arena it is called in; n, an arena of its own
    /// of n (the studio's refreshes take one, leaving the others to the render and the display).
    /// The result's bits do not depend on it.
    int threads = 0;
};

/// Auto's result on one frame and what it says of the denoised image.
struct Denoised {
    denoise::AutoResult result;
    Image relative;        ///< relativeError of the result (steering.h)
    double relMse = 0.0;   ///< estimatedRelMse of `relative`
    double seconds = 0.0;  ///< auto's wall time
    double meanSpp = 0.0;  ///< of the frame it ran on
};

/// The mean of a frame's sampleCount layer.
double meanSpp(const FrameBuffers& frame);

/// The automatic selection a refresh (or glint-final's last auto) runs: auto as glint-denoise
/// auto runs it at `quality`, its tuning the quality's when `options` names none, estimating the
/// result's error too; the bank of `bankSize` members (0: the quality's) of `filters` (empty: the
/// default bank's).
struct AutoRun {
    denoise::AutoOptions autoOptions;
    denoise::BankOptions bank;
};
AutoRun autoRun(const denoise::AutoOptions& options, denoise::AutoQuality quality, int bankSize = 0,
                const std::vector<std::string>& filters = {});

/// Auto on `frame` as `run` says (its seconds on the steady clock). Throws as
/// autoCompositeStreamed (Error(Cancelled) when the options' progress says stop).
Denoised denoiseFrame(const FrameBuffers& frame, const AutoRun& run);

/// The refreshes of one render: call importance() from Callbacks::importance and converged()
/// from Callbacks::converged (or, to run auto elsewhere, due(), denoise() and adopt()). Not
/// thread-safe except denoise(), which is const.
class Refresher {
  public:
    explicit Refresher(RefreshOptions options);

    /// Whether `frame` has grown enough since the last refresh for another (always before the
    /// first).
    bool due(const FrameBuffers& frame) const;
    /// Auto on `frame` with the options (estimateError on), on `threads` threads. Throws as
    /// autoCompositeStreamed (Error(Cancelled) when autoOptions.progress says stop).
    Denoised denoise(const FrameBuffers& frame) const;
    /// Makes `denoised` the latest refresh (counted, its seconds added).
    void adopt(Denoised denoised);
    /// The importance map from the latest refresh: importanceFromError of its relative error at
    /// the schedule's scale √(spp now / spp at the first refresh) (varianceOnly: that scale
    /// everywhere), pixels outside the focus at 0. Needs a refresh.
    std::shared_ptr<const Image> map() const;
    /// A map before any refresh, from the frame's own statistics: each pixel's variance of the
    /// mean relative to its colour (variance / (colour² + 0.01), over the channels), both taken
    /// as means over the pixel's 5 × 5 neighbourhood and from half B alone when the frame has
    /// half buffers (half A, which never decides, stays an unbiased estimate), the worst `focus`
    /// of the pixels open at weight 1, the others 0 (with focus 1: 1 everywhere). For a
    /// caller that does not wait for auto's first map (the studio's Keep Refining). `share` in
    /// (0, 1] narrows it to the worst share × focus (a short first adaptive pass).
    std::shared_ptr<const Image> provisional(const FrameBuffers& frame, double share = 1.0) const;
    /// Callbacks::importance's body: a refresh when due (auto run here), then its map; an empty
    /// pointer when nothing is due (the renderer keeps the map it has).
    std::shared_ptr<const Image> importance(const FrameBuffers& frame);
    /// Whether `frame` has more samples than the latest refresh's (always before the first).
    bool grew(const FrameBuffers& frame) const;
    /// Callbacks::converged's body (no pixel open under the latest map): a refresh now when the
    /// frame grew (auto's next map may name other pixels), then its map; an empty pointer when
    /// it did not (the render ends).
    std::shared_ptr<const Image> converged(const FrameBuffers& frame);

    /// The latest refresh (empty before the first).
    const std::optional<Denoised>& last() const { return m_last; }
    int refreshes() const { return m_refreshes; }
    double autoSeconds() const { return m_autoSeconds; }

  private:
    RefreshOptions m_options;
    AutoRun m_run;
    std::optional<Denoised> m_last;
    double m_startSpp = 0.0;
    int m_refreshes = 0;
    double m_autoSeconds = 0.0;
};

}  // namespace glint::pipeline
