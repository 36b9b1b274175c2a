#include "model/render_job.h"

#include <chrono>

#include "glint/image/error.h"

namespace glint::studio {

RenderJob::RenderJob(QObject* parent) : QObject(parent) {
    m_worker = std::thread([this] { workerLoop(); });
}

RenderJob::~RenderJob() {
    {
        std::lock_guard lock(m_mutex);
        m_quit = true;
        m_cancel = true;
        m_paused = false;
    }
    m_wake.notify_all();
    m_worker.join();
}

void RenderJob::setRenderer(std::shared_ptr<render::Renderer> renderer) {
    std::lock_guard lock(m_mutex);
    m_renderer = std::move(renderer);
}

std::uint64_t RenderJob::start(const render::Settings& settings, Steering steering) {
    std::uint64_t id = 0;
    {
        std::lock_guard lock(m_mutex);
        id = m_nextId++;
        m_pending = Request{id, settings, std::move(steering)};
        m_cancel = true;  // the running render (if any) stops at its next poll
        m_paused = false;
    }
    m_wake.notify_all();
    m_currentId = id;
    if (!m_busy) {
        m_busy = true;
        emit busyChanged(true);
    }
    return id;
}

void RenderJob::withScene(std::function<void(render::Scene&)> work,
                          std::function<void(const QString&)> done) {
    {
        std::lock_guard lock(m_mutex);
        m_edits.push_back({std::move(work), std::move(done)});
    }
    m_wake.notify_all();
}

void RenderJob::cancel() {
    {
        std::lock_guard lock(m_mutex);
        m_cancel = true;
        m_paused = false;
        if (m_pending) m_pending->cancelled = true;
    }
    m_wake.notify_all();
}

void RenderJob::setPaused(bool paused) {
    {
        std::lock_guard lock(m_mutex);
        const auto now = std::chrono::steady_clock::now();
        if (paused && !m_paused) m_pausedSince = now;
        if (!paused && m_paused) m_pausedTotal += now - m_pausedSince;
        m_paused = paused;
    }
    m_wake.notify_all();
}

bool RenderJob::stopping() const {
    std::lock_guard lock(m_mutex);
    return m_cancel || m_quit;
}

bool RenderJob::paused() const {
    std::lock_guard lock(m_mutex);
    return m_paused;
}

void RenderJob::deliver(std::function<void()> fn) {
    QMetaObject::invokeMethod(this, std::move(fn), Qt::QueuedConnection);
}

void RenderJob::workerLoop() {
    for (;;) {
        std::optional<Request> request;
        std::shared_ptr<render::Renderer> renderer;
        std::deque<SceneWork> edits;
        {
            std::unique_lock lock(m_mutex);
            m_wake.wait(lock, [&] { return m_quit || m_pending.has_value() || !m_edits.empty(); });
            if (m_quit) return;
            request.swap(m_pending);
            if (request) m_cancel = request->cancelled;
            renderer = m_renderer;
            edits.swap(m_edits);
        }
        // Scene work (look edits, saves) runs between renders, on the thread that renders.
        for (SceneWork& edit : edits) {
            QString error;
            try {
                if (!renderer) throw Error(ErrorKind::InvalidArgument, "no scene is open");
                edit.work(renderer->scene());
            } catch (const Error& e) {
                error = QString::fromStdString(e.what());
            } catch (const std::exception& e) {
                error = tr("internal error: %1").arg(e.what());
            }
            if (edit.done) deliver([done = std::move(edit.done), error] { done(error); });
        }
        if (request) runOne(*request, renderer);
    }
}

void RenderJob::runOne(const Request& request, std::shared_ptr<render::Renderer> renderer) {
    const std::uint64_t id = request.id;
    auto finishedBusy = [this, id] {
        if (id == m_currentId && m_busy) {
            m_busy = false;
            emit busyChanged(false);
        }
    };
    if (!renderer) {
        // A render cancelled before it began (its scene closed since) only ends.
        deliver([this, id, finishedBusy, cancelled = request.cancelled] {
            if (!cancelled) emit failed(id, tr("nothing to render: no scene is open"));
            finishedBusy();
        });
        return;
    }
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = Clock::now();
    {
        std::lock_guard lock(m_mutex);
        m_pausedTotal = {};
    }
    // Render time: the wall time since the start less the time spent paused.
    auto seconds = [this, t0] {
        std::lock_guard lock(m_mutex);
        const Clock::time_point now = Clock::now();
        const Clock::duration paused =
            m_pausedTotal + (m_paused ? now - m_pausedSince : Clock::duration{});
        return std::chrono::duration<double>(now - t0 - paused).count();
    };
    Clock::time_point lastProgress = t0;

    render::Callbacks callbacks;
    callbacks.cancel = [this] {
        // Pause holds the render here, between tiles; cancel (or a newer start) releases it.
        std::unique_lock lock(m_mutex);
        m_wake.wait(lock, [&] { return !m_paused || m_cancel || m_quit; });
        return m_cancel || m_quit;
    };
    callbacks.progress = [&](int pass, double fraction) {
        // At most ~30 updates a second reach the UI.
        const Clock::time_point now = Clock::now();
        if (now - lastProgress < std::chrono::milliseconds(33) && fraction < 1.0) return;
        lastProgress = now;
        deliver(
            [this, id, pass, fraction, s = seconds()] { emit progress(id, pass, fraction, s); });
    };
    callbacks.passDone = [&](int /*pass*/, const FrameBuffers& frame) {
        auto copy = std::make_shared<const FrameBuffers>(frame);
        const int spp = frame.metadata().spp;
        deliver([this, id, copy, spp, s = seconds()] { emit passDone(id, copy, spp, s); });
    };
    callbacks.importance = request.steering.importance;
    callbacks.converged = request.steering.converged;
    try {
        render::RenderResult result = renderer->render(request.settings, callbacks);
        result.stats.seconds = seconds();  // the renderer's wall time counts pauses
        auto frame = std::make_shared<const FrameBuffers>(std::move(result.frame));
        deliver([this, id, frame, stats = result.stats, finishedBusy] {
            emit finished(id, frame, stats);
            finishedBusy();
        });
    } catch (const Error& e) {
        const QString message = QString::fromStdString(e.what());
        deliver([this, id, message, finishedBusy] {
            emit failed(id, message);
            finishedBusy();
        });
    } catch (const std::exception& e) {
        const QString message = tr("internal error: %1").arg(e.what());
        deliver([this, id, message, finishedBusy] {
            emit failed(id, message);
            finishedBusy();
        });
    }
}

}  // namespace glint::studio
