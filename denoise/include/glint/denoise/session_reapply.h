// What the painting session (session.h) hands between threads when it re-applies its layers to
// a new render: a snapshot of its layers taken on its own thread, and the re-application
// prepared from it on a worker (Session::snapshot, Session::prepareReapply, Session::reapply).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

struct SessionCorrection;

/// What a layer is without its maps: enough to compute its output.
struct LayerSpec {
    // A constructor rather than an aggregate: {filter, params} needs no correction.
    LayerSpec(std::string filterName = {}, ParamValues filterParams = {},
              std::shared_ptr<const SessionCorrection> autoCorrection = {})
        : filter(std::move(filterName)),
          params(std::move(filterParams)),
          correction(std::move(autoCorrection)) {}

    std::string filter;
    ParamValues params;
    /// Auto's correction layer (filter kAutoCorrection): nothing to compute, the correction is
    /// carried as it is (Session::addCorrection). Session::layerSpecs() lists none.
    std::shared_ptr<const SessionCorrection> correction;
};

/// How the session treats its input.
struct SessionOptions {
    bool prefilter = false;       ///< filters read prefiltered features
    ParamValues prefilterParams;  ///< of prefilterFeatures
};

/// What a re-application on another thread needs of the session (Session::snapshot()).
struct SessionSnapshot {
    SessionOptions options;
    std::vector<LayerSpec> specs;   ///< Session::layerSpecs()
    std::vector<std::size_t> uses;  ///< per current layer: its entry of specs (a correction: none)
    /// Per current layer: its correction (auto's correction layer), else null.
    std::vector<std::shared_ptr<const SessionCorrection>> corrections;
    std::vector<Image> weights;  ///< per current layer
    std::uint64_t version = 0;   ///< Session::version() when taken
};

/// A re-application prepared off the session's thread (Session::prepareReapply).
struct SessionReapplication {
    FrameBuffers input;
    std::optional<FrameBuffers> filterInput;  ///< the prefiltered input, when the options say so
    std::vector<LayerSpec> specs;
    std::vector<std::shared_ptr<const Image>> outputs;  ///< one per spec
    Image composite;                                    ///< under the snapshot's weights
    std::uint64_t version = 0;                          ///< the snapshot's
};

}  // namespace glint::denoise
