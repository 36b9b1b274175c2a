#include "model/progressive_render.h"

#include <algorithm>
#include <atomic>
#include <optional>
#include <thread>

#include "glint/image/error.h"
#include "glint/render/settings_codec.h"

namespace glint::studio {

ProgressiveRender::ProgressiveRender(QObject* parent) : QObject(parent) {}

bool ProgressiveRender::applies(const render::Settings& settings) {
    return settings.integrator == render::Integrator::Path &&
           settings.sampler != render::SamplerKind::Stratified && !settings.region &&
           !settings.shard && settings.spp > 0;
}

render::Settings ProgressiveRender::refining(const render::Settings& settings) {
    render::Settings s = settings;
    s.adaptive = true;
    s.halfBuffers = true;
    s.minSpp = settings.spp;
    s.spp = std::max(settings.spp, std::min(kMaxSpp, settings.spp * kSppFactor));
    s.timeLimit = 0.0;
    s.importance.reset();
    return s;
}

bool ProgressiveRender::continues(const render::Settings& from, const render::Settings& settings,
                                  const FrameBuffers& frame) {
    if (!applies(settings) || render::encodeSettings(from) != render::encodeSettings(settings) ||
        (settings.sampler != render::SamplerKind::Sobol &&
         settings.sampler != render::SamplerKind::Independent) ||
        !frame.has(Layer::HalfSampleCount) || frame.metadata().nonFiniteSamples != 0)
        return false;
    const auto counts = frame.layer(Layer::SampleCount).data();
    return std::all_of(counts.begin(), counts.end(),
                       [spp = float(settings.spp)](float n) { return n >= spp; });
}

pipeline::RefreshOptions ProgressiveRender::refreshOptions() {
    pipeline::RefreshOptions o;
    // A refresh every time the mean spp doubled, as glint-final's: auto leaves the cores to the
    // render and the display in between.
    o.growth = 2.0;
    o.quality = denoise::AutoQuality::Fast;
    o.bankSize = 2;
    o.filters = {"cross-bilateral"};
    o.focus = 0.1;
    // Auto on every thread at the render's priority: on one thread at nice +5 (measured in
    // docs/lab/keep-refining.md) its map rarely came at all while the render ran, and under the
    // sanitizer a refresh never came in two minutes.
    o.threads = 0;
    return o;
}

// The steering of one render: its Refresher, the refresh running on a worker and its result.
struct ProgressiveRender::Steer {
    std::optional<pipeline::Refresher> refresher;
    double share = kFirstPassShare;  // of the next provisional map (above 1: none)
    std::function<bool()> stopping;
    std::atomic<bool> stop{false};
    std::mutex mutex;
    std::optional<pipeline::Denoised> ready;  // the worker's refresh, not adopted yet
    bool running = false;
    std::thread worker;
    std::shared_ptr<Shared> shared;

    ~Steer() {
        stop = true;
        if (worker.joinable()) worker.join();
    }
    // The map of the refresher's latest refresh, recorded as handed.
    std::shared_ptr<const Image> hand() {
        std::shared_ptr<const Image> map = refresher->map();
        std::lock_guard lock(shared->mutex);
        shared->handed = {map, std::make_shared<const pipeline::Denoised>(*refresher->last()),
                          refresher->refreshes()};
        return map;
    }
    // The map from the frame's own relative variance, until auto's first map: the first adaptive
    // pass on kFirstPassShare of the pixels the later ones take, each next one on twice the
    // share of the one before, up to all of them (passes double their samples a pixel: so the
    // first ones, beside the bar's render being denoised and journalled and auto's first
    // refresh, stay short); then none (the renderer keeps the last).
    std::shared_ptr<const Image> provisional(const FrameBuffers& frame) {
        if (refresher->last() || share > 1.0) return nullptr;
        auto map = refresher->provisional(frame, share);
        share *= 2.0;
        return map;
    }
    // Callbacks::importance, on the render's thread.
    std::shared_ptr<const Image> importance(const FrameBuffers& frame) {
        bool busy = false;
        {
            std::lock_guard lock(mutex);
            if (ready) {
                refresher->adopt(std::move(*ready));
                ready.reset();
                return hand();
            }
            busy = running;
        }
        if (busy) return provisional(frame);
        if (!refresher->due(frame)) return nullptr;
        // Auto on a worker while the render goes on. The first adaptive passes do not wait for
        // its map: the frame's own relative variance steers until it comes (without a map the
        // pass would take every pixel, as long as the whole start).
        std::shared_ptr<const Image> first = provisional(frame);
        if (worker.joinable()) worker.join();
        running = true;
        {
            std::lock_guard lock(shared->mutex);
            ++shared->activity.started;
        }
        worker = std::thread([this, copy = frame] {
            std::optional<pipeline::Denoised> d;
            try {
                d = refresher->denoise(copy);
            } catch (const std::exception&) {
                // Cancelled, a frame auto refuses, no memory: the map stays as it is.
            }
            {
                std::lock_guard lock(shared->mutex);
                ++shared->activity.finished;
            }
            std::lock_guard lock(mutex);
            ready = std::move(d);
            running = false;
        });
        return first;
    }
    // Callbacks::converged, on the render's thread: no pixel open under the latest map. The
    // render has nothing else to do: it waits for the refresh under way and takes its map, or
    // runs one more on the frame if it grew since the last (empty: it did not; the render ends).
    std::shared_ptr<const Image> converged(const FrameBuffers& frame) {
        if (worker.joinable()) worker.join();
        {
            std::lock_guard lock(mutex);
            if (ready) {
                refresher->adopt(std::move(*ready));
                ready.reset();
                return hand();
            }
        }
        if (stop.load() || (stopping && stopping()) || !refresher->grew(frame)) return nullptr;
        {
            std::lock_guard lock(shared->mutex);
            ++shared->activity.started;
        }
        std::shared_ptr<const Image> map;
        try {
            map = refresher->converged(frame);
        } catch (const std::exception&) {
            // Cancelled, a frame auto refuses, no memory: the render ends with what it has.
        }
        {
            std::lock_guard lock(shared->mutex);
            ++shared->activity.finished;
        }
        return map ? hand() : nullptr;
    }
};

RenderJob::Steering ProgressiveRender::steer(std::function<bool()> stopping) {
    auto steer = std::make_shared<Steer>();
    steer->stopping = std::move(stopping);
    steer->shared = m_shared;
    pipeline::RefreshOptions options = refreshOptions();
    Steer* s = steer.get();
    options.autoOptions.progress = [s](double) {
        return !s->stop.load() && !(s->stopping && s->stopping());
    };
    steer->refresher.emplace(std::move(options));
    return {[steer](int, const FrameBuffers& frame) { return steer->importance(frame); },
            [steer](int, const FrameBuffers& frame) { return steer->converged(frame); }};
}

ProgressiveRender::Handed ProgressiveRender::lastHanded() const {
    std::lock_guard lock(m_shared->mutex);
    return m_shared->handed;
}

ProgressiveRender::Activity ProgressiveRender::activity() const {
    std::lock_guard lock(m_shared->mutex);
    return m_shared->activity;
}

}  // namespace glint::studio
