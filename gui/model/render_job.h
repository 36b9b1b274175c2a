// A render on a worker thread: the renderer's Callbacks are re-emitted as signals on the thread
// that owns the job (appleseed's queued renderer callbacks), so the UI thread only draws.
// Starting a render while one runs cancels it; Pause blocks the render in its cancel poll;
// look edits are queued and applied on the worker between renders, never during one.
#pragma once

#include <QObject>
#include <QString>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "glint/image/frame_buffers.h"
#include "glint/render/renderer.h"

namespace glint::studio {

using FramePtr = std::shared_ptr<const FrameBuffers>;

class RenderJob : public QObject {
    Q_OBJECT
  public:
    explicit RenderJob(QObject* parent = nullptr);
    ~RenderJob() override;

    /// The renderer used by the next render (shared: a reference render may use another).
    void setRenderer(std::shared_ptr<render::Renderer> renderer);
    /// Steers an adaptive render, on the render's thread: render::Callbacks::importance (before
    /// each adaptive pass) and converged (when no pixel would take the next one).
    using ImportanceFn =
        std::function<std::shared_ptr<const Image>(int pass, const FrameBuffers& frame)>;
    struct Steering {
        ImportanceFn importance, converged;
    };
    /// Cancels the running render (if any) and starts one with `settings` (and `steering`, for
    /// an adaptive one: model/progressive_render.h). Returns its id.
    std::uint64_t start(const render::Settings& settings, Steering steering = {});
    /// True once the running render was asked to stop (cancelled, superseded, quitting): work
    /// its callbacks run should stop too. Any thread.
    bool stopping() const;
    /// Queues work on the scene (a look edit, a save) for the worker, which runs it between
    /// renders, never during one; `done` then runs on this object's thread with the error
    /// message (empty on success).
    void withScene(std::function<void(render::Scene&)> work,
                   std::function<void(const QString& error)> done = {});
    /// Stops the running render at its next tile boundary (it still delivers what it has); one
    /// requested but not yet begun stops at its first (and so still ends: `finished`, not busy).
    void cancel();
    void setPaused(bool paused);
    bool paused() const;
    /// True from start() until finished/failed of the last render was delivered.
    bool busy() const { return m_busy; }
    /// Id of the render whose results are being delivered (the latest started).
    std::uint64_t currentId() const { return m_currentId; }

  signals:
    /// A pass completed: the frame so far, the samples per pixel in it, seconds since start.
    void passDone(std::uint64_t id, glint::studio::FramePtr frame, int spp, double seconds);
    /// Progress within the render: pass index, fraction of the whole render, seconds so far.
    void progress(std::uint64_t id, int pass, double fraction, double seconds);
    /// The render ended (completed or cancelled) with its frame and statistics.
    void finished(std::uint64_t id, glint::studio::FramePtr frame,
                  const glint::render::RenderStats& stats);
    /// The render (or a queued scene edit) threw; the message names the problem.
    void failed(std::uint64_t id, const QString& message);
    void busyChanged(bool busy);

  private:
    struct Request {
        std::uint64_t id = 0;
        render::Settings settings;
        Steering steering;
        /// Cancelled before the worker took it: it still runs, stopping at its first poll, so
        /// that its end is reported (busy clears, a render gone on from a frame hands it back).
        bool cancelled = false;
    };
    void workerLoop();
    void runOne(const Request& request, std::shared_ptr<render::Renderer> renderer);
    void deliver(std::function<void()> fn);

    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::optional<Request> m_pending;
    struct SceneWork {
        std::function<void(render::Scene&)> work;
        std::function<void(const QString&)> done;
    };
    std::deque<SceneWork> m_edits;
    std::shared_ptr<render::Renderer> m_renderer;
    bool m_cancel = false;
    bool m_paused = false;
    // Time the running render spent paused (not render time): the total of finished pauses and
    // when the current one began.
    std::chrono::steady_clock::duration m_pausedTotal{};
    std::chrono::steady_clock::time_point m_pausedSince{};
    bool m_quit = false;
    std::uint64_t m_nextId = 1;
    std::uint64_t m_currentId = 0;  // UI thread only
    bool m_busy = false;            // UI thread only
    std::thread m_worker;
};

}  // namespace glint::studio
