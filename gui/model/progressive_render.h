// Keep refining (docs/studio.md, "Keep refining"): a whole-frame render of a scene goes on past
// the render bar's spp in adaptive passes steered where the denoised image is worst — the loop
// glint-final runs (glint/pipeline/refresh.h: auto with its per-pixel error of the denoised image,
// made into the renderer's importance map, again as the samples grow) — until the cap, a new
// render (a look or camera edit, Render) or Cancel. The frame at the bar's spp is the finished
// render as without refining (the session, the first denoise, the journal); later passes are shown
// denoised by the session's layers (model/progressive_denoise.h), which refreshes never touch.
// Auto never runs on the UI thread nor holds a render that has pixels to sample: each refresh runs
// on a worker of its own while the render goes on, and its map steers the passes after it; until
// the first one, the frame's own relative variance does (Refresher::provisional). When no pixel
// is left open, the render waits for the refresh under way, or runs one more on the grown frame,
// and goes on where its map says; it ends when a refresh of the frame as it is opens no pixel.
// No widgets here.
#pragma once

#include <QObject>

#include <functional>
#include <memory>
#include <mutex>

#include "glint/image/image.h"
#include "glint/pipeline/refresh.h"
#include "glint/render/settings.h"
#include "model/render_job.h"

namespace glint::studio {

class ProgressiveRender : public QObject {
    Q_OBJECT
  public:
    /// A refining render takes at most the bar's spp times this a pixel.
    static constexpr int kSppFactor = 64;
    /// and never more than this.
    static constexpr int kMaxSpp = 4096;
    /// The first adaptive pass takes this share of the pixels the later ones take, the next
    /// ones twice the share of the one before (until auto's first map: the worst by their own
    /// relative variance), so that the first images come sooner.
    static constexpr double kFirstPassShare = 0.25;

    explicit ProgressiveRender(QObject* parent = nullptr);

    /// The artist's toggle (Render ▸ Keep Refining).
    void setEnabled(bool enabled) { m_enabled = enabled; }
    bool enabled() const { return m_enabled; }
    /// Whether a render with `settings` can refine: the path integrator, a sampler adaptive
    /// sampling takes, the whole frame.
    static bool applies(const render::Settings& settings);
    /// The refining render of the bar's `settings`: adaptive with half buffers (auto's error
    /// needs them), every pixel first at the bar's spp, then at most kSppFactor times it.
    static render::Settings refining(const render::Settings& settings);
    /// Whether the refining render of the bar's `settings` can go on from `frame`, the finished
    /// render of the bar's `from` (Settings::continueFrom), rather than render the bar's spp
    /// again: the same settings (every named one), a sampler the renderer goes on with (sobol,
    /// independent), half buffers in the frame (auto's error needs them), no sample discarded,
    /// and every pixel at least at the bar's spp.
    static bool continues(const render::Settings& from, const render::Settings& settings,
                          const FrameBuffers& frame);
    /// The studio's refreshes: auto at quality fast on a small bank of cross-bilateral, on one
    /// thread, the map open on the worst tenth of the pixels (short passes), again once the mean
    /// spp doubled.
    static pipeline::RefreshOptions refreshOptions();
    /// The steering of one refining render (RenderJob::start's); `stopping` (polled by auto)
    /// tells when the render was cancelled or superseded.
    RenderJob::Steering steer(std::function<bool()> stopping);

    /// The latest map handed to the renderer and the refresh it came from (tests).
    struct Handed {
        std::shared_ptr<const Image> map;
        std::shared_ptr<const pipeline::Denoised> from;
        int refreshes = 0;  ///< of the render that took it
    };
    Handed lastHanded() const;
    /// Auto's refreshes started and finished so far, over all renders (benchmarks, tests).
    struct Activity {
        int started = 0;
        int finished = 0;
    };
    Activity activity() const;

  private:
    struct Steer;
    /// What the renders' steerings handed last, shared with them (they may outlive this).
    struct Shared {
        std::mutex mutex;
        Handed handed;
        Activity activity;
    };

    bool m_enabled = false;
    std::shared_ptr<Shared> m_shared = std::make_shared<Shared>();
};

}  // namespace glint::studio
