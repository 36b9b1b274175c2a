// The one progressive render loop (pbrt-v4's ImageTileIntegrator::Render, Mitsuba's block loop):
// pass sizes, the time limit, parallel work items, cancel polling, progress and per-pass
// snapshots live here; an integrator supplies the work of one item of one pass.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <memory>
#include <mutex>
#include <optional>

#include <tbb/task_arena.h>

#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"
#include "glint/render/settings.h"

namespace glint::render {

/// One pass: `count` samples per pixel following the `first` already done (the block of the
/// whole render's sample sequence a stratified sampler stratifies over), of which a shard takes
/// samples [begin, end) (all of them unless RenderLoop::restrictSamples was called).
struct PassInfo {
    int index = 0;
    int first = 0;
    int count = 0;
    int begin = 0;
    int end = 0;
    /// An adaptive pass: only the pixels PassWork::planAdaptivePass chose take `count` more
    /// samples each, continuing their own sample sequences (begin and end are not used).
    bool adaptive = false;
};

class RenderLoop;

/// What an integrator gives the loop.
class PassWork {
  public:
    virtual ~PassWork() = default;
    /// Work items of a preparatory pass the loop runs before the first pass (Metropolis's
    /// bootstrap), polling cancel and reporting progress as in any pass; 0: none.
    virtual std::size_t setupItems() const { return 0; }
    /// The preparatory pass's cost in samples per pixel: its share of the progress of a
    /// render of fixed spp is setupSpp() / (setupSpp() + spp).
    virtual double setupSpp() const { return 0.0; }
    /// Runs one item of the preparatory pass.
    virtual void runSetup(std::size_t /*item*/, const RenderLoop& /*loop*/) {}
    /// After the preparatory pass completed; false when no pass is needed (the loop ends).
    virtual bool setupCompleted() { return true; }
    /// Work items of every pass (tiles, groups of Metropolis chains).
    virtual std::size_t items() const = 0;
    /// Runs one item of a pass. Long items may poll loop.stopRequested() and return early; the
    /// loop then ends the render after this pass without counting it.
    virtual void run(const PassInfo& pass, std::size_t item, const RenderLoop& loop) = 0;
    /// The pixels an item covers, for Callbacks::tileDone (nullopt: it is not a tile).
    virtual std::optional<Rect> itemRect(std::size_t /*item*/) const { return std::nullopt; }
    /// Adaptive sampling: chooses the pixels that take the next pass (those not converged),
    /// returning how many there are; 0 ends the render.
    virtual std::uint64_t planAdaptivePass() { return 0; }
    /// Adaptive sampling: replaces the importance map (Callbacks::importance); throws
    /// glint::Error(InvalidArgument) for a map that is not one.
    virtual void setImportance(std::shared_ptr<const Image> /*weights*/) {}
    /// Adaptive sampling: the pixels an adaptive pass chooses from (the render region); 0 keeps
    /// every adaptive pass at RenderLoop::kAdaptiveStep.
    virtual std::uint64_t adaptivePixels() const { return 0; }
    /// The pixel samples item `item` took in the last adaptive pass.
    virtual std::uint64_t adaptiveItemSamples(std::size_t /*item*/) const { return 0; }
    /// After each completed pass (before any snapshot of it is taken).
    virtual void passCompleted(const PassInfo& /*pass*/) {}
    /// The frame of every completed pass so far (for Callbacks::passDone).
    virtual FrameBuffers snapshot() = 0;
};

/// How one loop ended.
struct LoopResult {
    int passes = 0;
    int completedSpp = 0;
    bool cancelled = false;
    /// Pixel samples of the tiles finished (itemRect area × pass spp), including those of a
    /// cancelled pass.
    std::uint64_t samples = 0;
};

/// Runs the work's preparatory pass, if any, then passes of sizes 1, 1, 2, 4 … 64 spp until
/// `spp` is reached, the time budget runs out or the caller cancels. With adaptive sampling
/// (setAdaptive), the passes after the adaptive start go only to the pixels the work chooses,
/// until it chooses none. Progress of this loop maps to [progressBegin, progressEnd] of the
/// render.
class RenderLoop {
  public:
    RenderLoop(int spp, double timeBudget, const Callbacks& callbacks, tbb::task_arena& arena,
               double progressBegin = 0.0, double progressEnd = 1.0);

    /// Runs the passes. With `reportPasses`, Callbacks::passDone (when set) receives
    /// work.snapshot() after each completed pass.
    LoopResult run(PassWork& work, bool reportPasses = true);

    /// Renders only per-pixel samples [begin, end) of the spp (a shard, Settings::shard): the
    /// passes keep the sizes and boundaries of the whole render, and each takes its share of
    /// the range. Needs a fixed spp (no time budget).
    void restrictSamples(int begin, int end);

    /// Adaptive sampling: uniform passes up to `startSpp` samples per pixel, then adaptive
    /// passes (PassWork::planAdaptivePass) of adaptiveStep() samples at most; `spp` bounds each
    /// pixel (0: only the time budget and convergence end the render).
    void setAdaptive(int startSpp);
    /// Adaptive sampling: the film already holds `spp` samples in its fullest pixel and at
    /// least the adaptive start in every other (a finished render gone on from,
    /// Settings::continueFrom): the loop begins with its adaptive passes, its count of samples
    /// a pixel at `spp`. After setAdaptive.
    void continueAt(int spp);
    /// The most samples an adaptive pass adds to a pixel while many are open (Cycles checks
    /// every 16).
    static constexpr int kAdaptiveStep = 16;
    /// The most an adaptive pass adds to a pixel when few are open.
    static constexpr int kMaxAdaptiveStep = 256;
    /// The samples of the film's pixels an adaptive pass carries at least, when its step allows:
    /// a pass over few open pixels would otherwise cost more in its fixed part (planning, the
    /// tiles' loop, the threads meeting at its end) than in its samples (docs/lab/
    /// adaptive-dof.md, "Why adaptive loses on dof").
    static constexpr int kAdaptivePassSpp = 2;
    /// An adaptive pass's step over `active` open pixels of `pixels`: kAdaptiveStep doubled
    /// while the pass carries fewer than kAdaptivePassSpp × pixels samples, up to
    /// kMaxAdaptiveStep (kAdaptiveStep when pixels is 0).
    static int adaptiveStep(std::uint64_t active, std::uint64_t pixels);

    /// Polls Callbacks::cancel (serialised); true once the render should stop.
    bool stopRequested() const;

  private:
    double elapsed() const;
    /// Runs items [0, items) in parallel through runItem(i) (which returns the item's tile,
    /// if any), polling cancel before each and then reporting the tile and
    /// progress(pass, fraction(items finished)) under the callback lock.
    template <class RunItem, class Fraction>
    void runItems(std::size_t items, int pass, const RunItem& runItem, const Fraction& fraction);

    int m_spp;
    double m_budget;
    const Callbacks& m_callbacks;
    tbb::task_arena& m_arena;
    double m_begin, m_end;
    int m_sampleBegin = 0, m_sampleEnd = 0;  // the samples taken (a shard), or all of them
    int m_adaptiveStart = 0;                 // uniform passes up to this spp; 0: not adaptive
    int m_continueAt = 0;                    // samples a pixel the film holds at the start
    mutable std::mutex m_callbackMutex;
    mutable std::atomic<bool> m_cancelled{false};
    std::chrono::steady_clock::time_point m_start;
};

}  // namespace glint::render
