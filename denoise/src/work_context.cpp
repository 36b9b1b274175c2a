// WorkContext: counts work for the progress callback and stops loops on cancellation.
#include "glint/denoise/progress.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <mutex>

#include "glint/image/error.h"

namespace glint::denoise {

struct WorkContext::State {
    ProgressFn progress;
    std::atomic<bool> cancelled{false};
    std::atomic<std::int64_t> done{0};
    std::atomic<std::int64_t> expected{0};  // 0: unknown (grows with each loop)
    std::mutex callbackMutex;
    double lastReported = -1.0;  // guarded by callbackMutex
};

WorkContext::WorkContext(ProgressFn progress) : m_state(std::make_unique<State>()) {
    m_state->progress = std::move(progress);
}

WorkContext::~WorkContext() = default;

void WorkContext::expectWork(std::int64_t units) {
    m_state->expected.store(std::max<std::int64_t>(units, 1));
}

bool WorkContext::cancelled() const {
    return m_state->cancelled.load(std::memory_order_relaxed);
}

void WorkContext::cancel() {
    m_state->cancelled.store(true);
}

void WorkContext::throwIfCancelled() const {
    if (cancelled()) throw Error(ErrorKind::Cancelled, "cancelled");
}

void WorkContext::addWork(std::int64_t units) {
    State& s = *m_state;
    const std::int64_t done = s.done.fetch_add(units) + units;
    if (!s.progress || cancelled()) return;
    const std::int64_t expected = s.expected.load();
    // Never report 1 before finish(): the last loop may still be running.
    const double fraction = expected > 0 ? std::min(0.999, double(done) / double(expected)) : 0.0;
    // Report in steps of 1/256 at most; a busy callback is skipped, not waited for.
    std::unique_lock<std::mutex> lock(s.callbackMutex, std::try_to_lock);
    if (!lock.owns_lock() || fraction < s.lastReported + 1.0 / 256.0) return;
    s.lastReported = fraction;
    if (!s.progress(fraction)) cancel();
}

bool WorkContext::poll() {
    State& s = *m_state;
    if (!s.progress || cancelled()) return !cancelled();
    std::unique_lock<std::mutex> lock(s.callbackMutex, std::try_to_lock);
    if (lock.owns_lock() && !s.progress(std::max(0.0, s.lastReported))) cancel();
    return !cancelled();
}

void WorkContext::parallelFor(int begin, int end, const std::function<void(int)>& fn,
                              std::int64_t unitsPerIndex) {
    throwIfCancelled();
    if (end <= begin) return;
    State& s = *m_state;
    // Without an announced total, each loop extends the expected work by its own size.
    if (s.expected.load() == 0 || s.expected.load() < s.done.load() + (end - begin) * unitsPerIndex)
        s.expected.store(
            std::max(s.expected.load(), s.done.load() + (end - begin) * unitsPerIndex));
    tbb::parallel_for(tbb::blocked_range<int>(begin, end), [&](const tbb::blocked_range<int>& r) {
        for (int i = r.begin(); i != r.end(); ++i) {
            if (cancelled()) return;
            fn(i);
            addWork(unitsPerIndex);
        }
    });
    throwIfCancelled();
}

void WorkContext::finish() {
    State& s = *m_state;
    if (!s.progress || cancelled()) return;
    const std::lock_guard<std::mutex> lock(s.callbackMutex);
    s.lastReported = 1.0;
    s.progress(1.0);  // the work is done: a "stop" now changes nothing
}

}  // namespace glint::denoise
