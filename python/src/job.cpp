// Long work off the GIL: a worker thread runs Glint while the calling thread wakes every 50 ms,
// with the GIL, to call the Python progress callback and check for Ctrl-C.
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "bindings.h"
#include "glint/image/error.h"

namespace glint::python {

Job::Job(py::object progress) : m_progress(std::move(progress)) {
    if (!m_progress.is_none() && !PyCallable_Check(m_progress.ptr()))
        throw Error(ErrorKind::InvalidArgument, "is not callable", {}, "progress");
}

std::function<bool(double)> Job::progressFn() {
    return [this](double fraction) {
        report(fraction);
        return !stopping();
    };
}

void Job::run(const std::function<void()>& work) {
    std::mutex mutex;
    std::condition_variable done;
    bool finished = false;
    std::exception_ptr workError;
    std::optional<py::error_already_set> pythonError;
    bool refused = false;  // the callback returned False
    double lastReported = -1.0;

    // Calls the callback with the fraction done (GIL held); records what stops the work.
    auto poll = [&](bool final) {
        if (PyErr_CheckSignals() != 0) {
            pythonError.emplace();
            m_stop = true;
            return;
        }
        const double fraction = m_fraction.load(std::memory_order_relaxed);
        if (m_progress.is_none() || fraction == lastReported) return;
        lastReported = fraction;
        try {
            const py::object answer = m_progress(fraction);
            if (answer.is(py::bool_(false)) && !final) {
                refused = true;
                m_stop = true;
            }
        } catch (py::error_already_set& e) {
            pythonError.emplace(std::move(e));
            m_stop = true;
        }
    };

    std::thread worker;
    {
        py::gil_scoped_release release;
        worker = std::thread([&] {
            try {
                work();
            } catch (...) {
                workError = std::current_exception();
            }
            std::lock_guard lock(mutex);
            finished = true;
            done.notify_all();
        });
    }
    for (;;) {
        bool over = false;
        {
            py::gil_scoped_release release;
            std::unique_lock lock(mutex);
            over = done.wait_for(lock, std::chrono::milliseconds(50), [&] { return finished; });
        }
        if (over) break;
        if (!pythonError) poll(false);
    }
    {
        py::gil_scoped_release release;
        worker.join();
    }
    if (pythonError) throw std::move(*pythonError);
    if (workError) {
        try {
            std::rethrow_exception(workError);
        } catch (const Error& e) {
            if (e.kind() != ErrorKind::Cancelled || !refused) throw;
        }
    }
    if (refused)
        throw Error(ErrorKind::Cancelled, "cancelled: the progress callback returned False");
    report(1.0);
    poll(true);
    if (pythonError) throw std::move(*pythonError);
}

}  // namespace glint::python
