// The heavy parts of making a painting session, shared by the session adapter (on its workers)
// and the autosave recovery (model/recovery.h): the filters' input, a session with layers carried
// over, and a re-application of the layers to a new render. They touch no live session: safe on
// a worker thread.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "glint/denoise/session.h"
#include "model/render_job.h"

namespace glint::studio {

/// The filters' input: `frame`, or a copy with its features prefiltered when `options` say so.
FramePtr filterInputFor(FramePtr frame, const denoise::SessionOptions& options,
                        const denoise::ProgressFn& progress = {});

/// A session on `frame` with `carry` layers (outputs computed on `filterInput`; auto's
/// correction carried as it is), their weights and names set where given: how a new session
/// keeps the painting.
denoise::Session buildSession(FramePtr frame, FramePtr filterInput,
                              const denoise::SessionOptions& options,
                              const std::vector<denoise::LayerSpec>& carry,
                              const std::vector<Image>& carryWeights,
                              const std::vector<std::string>& carryNames,
                              const denoise::ProgressFn& progress = {});

/// What re-applying the layers to a new render needs: the filters' input, and the session's
/// copy of the render with its outputs and composite under the snapshot's weights.
struct Reapplied {
    FramePtr filterInput;
    std::shared_ptr<denoise::Session::Reapplication> prepared;
};
/// Computes a re-application of `snapshot`'s layers to `frame`.
Reapplied computeReapply(FramePtr frame, const denoise::Session::Snapshot& snapshot,
                         const denoise::ProgressFn& progress = {});

}  // namespace glint::studio
