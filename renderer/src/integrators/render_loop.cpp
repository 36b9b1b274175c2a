#include "integrators/render_loop.h"

#include <algorithm>

#include "glint/image/error.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

namespace glint::render {

using Clock = std::chrono::steady_clock;

RenderLoop::RenderLoop(int spp, double timeBudget, const Callbacks& callbacks,
                       tbb::task_arena& arena, double progressBegin, double progressEnd)
    : m_spp(spp),
      m_budget(timeBudget),
      m_callbacks(callbacks),
      m_arena(arena),
      m_begin(progressBegin),
      m_end(progressEnd),
      m_sampleEnd(spp),
      m_start(Clock::now()) {}

void RenderLoop::restrictSamples(int begin, int end) {
    GLINT_CHECK(m_spp > 0 && m_budget <= 0.0 && 0 <= begin && begin < end && end <= m_spp,
                "a sample range needs a fixed spp and a non-empty range inside it");
    m_sampleBegin = begin;
    m_sampleEnd = end;
}

void RenderLoop::setAdaptive(int startSpp) {
    GLINT_CHECK(startSpp > 0 && m_sampleBegin == 0 && (m_spp == 0 || m_sampleEnd == m_spp),
                "adaptive sampling starts after at least one sample and takes every sample");
    m_adaptiveStart = m_spp > 0 ? std::min(startSpp, m_spp) : startSpp;
}

void RenderLoop::continueAt(int spp) {
    GLINT_CHECK(m_adaptiveStart > 0 && spp >= m_adaptiveStart && (m_spp == 0 || spp <= m_spp),
                "a render goes on from a film past its adaptive start, within its spp");
    m_continueAt = spp;
}

int RenderLoop::adaptiveStep(std::uint64_t active, std::uint64_t pixels) {
    int step = kAdaptiveStep;
    while (step < kMaxAdaptiveStep && active * std::uint64_t(step) < kAdaptivePassSpp * pixels)
        step *= 2;
    return step;
}

double RenderLoop::elapsed() const {
    return std::chrono::duration<double>(Clock::now() - m_start).count();
}

bool RenderLoop::stopRequested() const {
    if (m_cancelled.load()) return true;
    if (m_callbacks.cancel) {
        const std::lock_guard<std::mutex> lock(m_callbackMutex);
        if (m_callbacks.cancel()) m_cancelled.store(true);
    }
    return m_cancelled.load();
}

template <class RunItem, class Fraction>
void RenderLoop::runItems(std::size_t items, int pass, const RunItem& runItem,
                          const Fraction& fraction) {
    std::atomic<std::size_t> itemsDone{0};
    m_arena.execute([&] {
        tbb::parallel_for(
            tbb::blocked_range<std::size_t>(0, items, 1),
            [&](const tbb::blocked_range<std::size_t>& range) {
                for (std::size_t i = range.begin(); i != range.end(); ++i) {
                    if (stopRequested()) return;
                    const std::optional<Rect> rect = runItem(i);
                    if (!m_callbacks.tileDone && !m_callbacks.progress) continue;
                    // Counted under the callback lock, so that reported progress never goes
                    // backwards when two items finish at once.
                    const std::lock_guard<std::mutex> lock(m_callbackMutex);
                    const std::size_t finished = ++itemsDone;
                    if (m_callbacks.tileDone && rect) m_callbacks.tileDone(*rect);
                    if (m_callbacks.progress) m_callbacks.progress(pass, fraction(finished));
                }
            },
            tbb::simple_partitioner());
    });
}

LoopResult RenderLoop::run(PassWork& work, bool reportPasses) {
    LoopResult result;
    const bool timed = m_budget > 0.0;
    const std::size_t items = work.items();
    std::atomic<std::uint64_t> samples{0};
    // `done` walks the whole render's sample sequence; `taken` counts the samples of it this
    // loop renders (all of them unless restrictSamples() chose a shard).
    int done = m_continueAt, taken = m_continueAt, pass = 0;
    const int share = m_spp > 0 ? m_sampleEnd - m_sampleBegin : 0;
    // Progress after `units` samples per pixel, the preparatory pass's setupSpp() included.
    const double setupSpp = work.setupSpp();
    auto progressAfter = [&](double units) {
        const double f =
            m_spp > 0 ? units / (setupSpp + double(share)) : std::min(1.0, elapsed() / m_budget);
        return m_begin + (m_end - m_begin) * f;
    };

    // The preparatory pass, then the work's verdict on whether passes follow.
    if (const std::size_t setupItems = work.setupItems(); setupItems > 0) {
        runItems(
            setupItems, 0,
            [&](std::size_t i) {
                work.runSetup(i, *this);
                return std::optional<Rect>();
            },
            [&](std::size_t finished) {
                return progressAfter(double(finished) / double(setupItems) * setupSpp);
            });
        if (m_cancelled.load() || !work.setupCompleted()) {
            result.cancelled = m_cancelled.load();
            return result;
        }
    }

    double secondsPerSpp = 0.0, secondsPerSample = 0.0;
    while (!m_cancelled.load()) {
        // Past the adaptive start, the work chooses each pass's pixels and each pixel stops at
        // spp on its own.
        const bool adaptive = m_adaptiveStart > 0 && done >= m_adaptiveStart;
        if (!adaptive && m_spp > 0 && done >= m_sampleEnd) break;
        // The first pass always completes: a tiny time limit still gives a 1-spp image.
        if (timed && done > 0 && elapsed() >= m_budget) break;
        if (m_spp <= 0 && !timed) break;
        // Pass sizes double (1, 1, 2, 4, ... up to 64 spp) for quick early feedback; under a time
        // limit they are also cut to what the remaining time allows by the measured rate.
        int count = std::clamp(done, 1, 64);
        if (adaptive) {
            // The caller may steer this pass with a new importance map made from the frame.
            auto ask = [&](const auto& callback) {
                FrameBuffers frame = work.snapshot();
                frame.metadata().spp = taken;
                const std::lock_guard<std::mutex> lock(m_callbackMutex);
                return std::shared_ptr<const Image>(callback(pass, frame));
            };
            if (m_callbacks.importance)
                if (auto weights = ask(m_callbacks.importance))
                    work.setImportance(std::move(weights));
            std::uint64_t active = work.planAdaptivePass();
            // Every pixel converged or at spp: the caller may lower the threshold by its map.
            for (int retry = 0;
                 active == 0 && m_callbacks.converged && retry < kMaxConvergedRetries; ++retry) {
                auto weights = ask(m_callbacks.converged);
                if (!weights) break;
                work.setImportance(std::move(weights));
                active = work.planAdaptivePass();
            }
            if (active == 0) break;
            // Passes double as the uniform ones do, up to the step the open pixels allow.
            count = std::min(std::clamp(done, 1, kMaxAdaptiveStep),
                             adaptiveStep(active, work.adaptivePixels()));
            if (timed && secondsPerSample > 0.0)
                count = int(std::clamp((m_budget - elapsed()) / (secondsPerSample * double(active)),
                                       1.0, double(count)));
        } else {
            if (m_adaptiveStart > 0) count = std::min(count, m_adaptiveStart - done);
            if (m_spp > 0) count = std::min(count, m_spp - done);
            if (timed && secondsPerSpp > 0.0) {
                // Clamped in double: a fast pass on a tiny film gives ratios beyond INT_MAX.
                count = int(std::clamp((m_budget - elapsed()) / secondsPerSpp, 1.0, double(count)));
            }
        }
        // A shard renders its part of this pass; a pass wholly outside it is skipped. (An
        // adaptive pass is no shard's: each pixel's samples continue from its own count.)
        const int begin = adaptive ? done : std::max(done, m_sampleBegin);
        const int end = adaptive
                            ? done + count
                            : std::min(done + count, m_sampleEnd > 0 ? m_sampleEnd : done + count);
        if (begin >= end) {
            done += count;
            continue;
        }
        const int rendered = end - begin;
        const PassInfo info{pass, done, count, begin, end, adaptive};
        const double passStart = elapsed();
        const std::uint64_t samplesBefore = samples.load();
        runItems(
            items, pass,
            [&](std::size_t i) {
                work.run(info, i, *this);
                const std::optional<Rect> rect = work.itemRect(i);
                if (adaptive)
                    samples += work.adaptiveItemSamples(i);
                else if (rect)
                    samples += std::uint64_t(rect->width()) * rect->height() * rendered;
                return rect;
            },
            [&](std::size_t finished) {
                return progressAfter(setupSpp + double(taken) +
                                     double(finished) / double(items) * rendered);
            });
        if (m_cancelled.load()) break;
        const double passSeconds = elapsed() - passStart;
        secondsPerSpp = passSeconds / double(rendered);
        if (const std::uint64_t passSamples = samples.load() - samplesBefore; passSamples > 0)
            secondsPerSample = passSeconds / double(passSamples);
        done += count;
        taken += rendered;
        // An adaptive render's spp is the most any pixel took.
        if (adaptive && m_spp > 0) taken = std::min(taken, m_spp);
        ++pass;
        work.passCompleted(info);
        if (reportPasses && m_callbacks.passDone) {
            FrameBuffers frame = work.snapshot();
            frame.metadata().spp = taken;
            m_callbacks.passDone(pass - 1, frame);
        }
    }
    result.passes = pass;
    result.completedSpp = taken;
    result.cancelled = m_cancelled.load();
    result.samples = samples.load();
    return result;
}

}  // namespace glint::render
