// Background work for the studio: a task runs on a worker thread and hands its result to the
// UI thread through a queued call, so the UI thread only draws and dispatches (tev's background
// loading, appleseed's queued renderer callbacks). Tasks with the same key supersede each other:
// starting one cancels the older (its cancel flag is set) and drops its result.
#pragma once

#include <QObject>
#include <QString>

#include <atomic>
#include <cstdint>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <thread>

#include "glint/image/error.h"

namespace glint::studio {

class TaskRunner : public QObject {
    Q_OBJECT
  public:
    /// Set when a newer task of the same key started (or the runner is destroyed): the work
    /// should stop (filters: return false from their progress callback).
    using CancelFlag = std::shared_ptr<std::atomic<bool>>;

    explicit TaskRunner(QObject* parent = nullptr) : QObject(parent) {}
    /// Cancels every task and waits for their threads (whose results are then dropped).
    ~TaskRunner() override {
        for (auto& [key, flag] : m_latest) flag->store(true);
        for (auto& [id, thread] : m_threads) thread.join();
    }

    /// Runs `work(cancel)` on a worker thread; `done(result)` then runs on this object's thread
    /// unless the task was superseded. A glint::Error from the work goes to `failed` (a
    /// cancellation is dropped silently).
    template <class R>
    void run(const QString& key, std::function<R(const CancelFlag&)> work,
             std::function<void(R)> done, std::function<void(const QString&)> failed = {}) {
        CancelFlag cancel = std::make_shared<std::atomic<bool>>(false);
        auto it = m_latest.find(key);
        if (it != m_latest.end()) it->second->store(true);
        m_latest[key] = cancel;
        ++m_pending;
        emit busyChanged(true);
        const std::uint64_t id = m_nextThread++;
        m_threads[id] = std::thread([this, id, key, cancel, work = std::move(work),
                                     done = std::move(done), failed = std::move(failed)]() mutable {
            std::shared_ptr<R> result;
            QString error;
            bool cancelled = false;
            try {
                result = std::make_shared<R>(work(cancel));
            } catch (const Error& e) {
                cancelled = e.kind() == ErrorKind::Cancelled;
                error = QString::fromStdString(e.what());
            } catch (const std::exception& e) {
                error = QStringLiteral("internal error: ") + QString::fromStdString(e.what());
            }
            // Delivered on the runner's thread; dropped if the runner is gone.
            QMetaObject::invokeMethod(
                this,
                [this, id, key, cancel, result, error, cancelled, done = std::move(done),
                 failed = std::move(failed)] {
                    // The thread has nothing left to do but return.
                    auto thread = m_threads.find(id);
                    if (thread != m_threads.end()) {
                        thread->second.join();
                        m_threads.erase(thread);
                    }
                    --m_pending;
                    const bool current = !cancel->load();
                    if (current && result && done) done(std::move(*result));
                    if (current && !result && !cancelled && failed) failed(error);
                    if (m_latest.count(key) && m_latest[key] == cancel) m_latest.erase(key);
                    if (m_pending == 0) emit busyChanged(false);
                },
                Qt::QueuedConnection);
        });
    }

    /// Cancels the running task of `key`, if any (its result will be dropped).
    void cancel(const QString& key) {
        auto it = m_latest.find(key);
        if (it == m_latest.end()) return;
        it->second->store(true);
        m_latest.erase(it);
    }

    /// Tasks whose results have not been delivered yet.
    int pending() const { return m_pending; }

  signals:
    void busyChanged(bool busy);

  private:
    std::map<QString, CancelFlag> m_latest;
    std::map<std::uint64_t, std::thread> m_threads;
    std::uint64_t m_nextThread = 1;
    int m_pending = 0;
};

}  // namespace glint::studio
