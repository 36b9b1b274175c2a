// Progress and cancellation of long denoise operations (a filter, the feature prefilter, a bank),
// in the spirit of Open Image Denoise's progress monitor: a callback receives the fraction done
// and returns false to stop; the operation then throws glint::Error(ErrorKind::Cancelled).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

namespace glint::denoise {

/// Receives the fraction done in [0, 1]; returns false to stop the operation. Calls are
/// serialised but may come from worker threads.
using ProgressFn = std::function<bool(double fraction)>;

/// What a running operation uses for its parallel loops: it counts work for the progress
/// callback and stops handing out work once cancelled. Filters receive one in Filter::apply.
class WorkContext {
  public:
    /// A context reporting to `progress` (may be empty: then it only runs loops).
    explicit WorkContext(ProgressFn progress = {});
    ~WorkContext();
    WorkContext(const WorkContext&) = delete;
    WorkContext& operator=(const WorkContext&) = delete;

    /// Announces how many work units (rows, usually) all loops of the operation process in
    /// total, for the progress fraction; without it the fraction grows towards 1 by the units
    /// of the loops run so far.
    void expectWork(std::int64_t units);

    /// Runs fn(i) for every i in [begin, end) in parallel in the caller's TBB arena; each index
    /// counts `unitsPerIndex` work units. Once cancelled, the remaining indices are skipped
    /// (each thread finishes the index it is on) and Error(Cancelled) is thrown after the loop.
    void parallelFor(int begin, int end, const std::function<void(int)>& fn,
                     std::int64_t unitsPerIndex = 1);

    /// Counts units done outside parallelFor (a serial step) and reports progress.
    void addWork(std::int64_t units);

    /// Asks the callback again with the fraction last reported (an operation waiting on something
    /// outside Glint, such as a program, calls it to learn whether to stop); returns false once
    /// cancelled.
    bool poll();

    /// True once the callback returned false or cancel() was called.
    bool cancelled() const;
    /// Stops the operation at its next check.
    void cancel();
    /// Throws glint::Error(Cancelled) when cancelled.
    void throwIfCancelled() const;

    /// Reports completion (fraction 1) unless cancelled.
    void finish();

  private:
    struct State;
    std::unique_ptr<State> m_state;
};

}  // namespace glint::denoise
