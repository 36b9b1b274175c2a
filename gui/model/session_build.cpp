#include "model/session_build.h"

#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"

namespace glint::studio {

FramePtr filterInputFor(FramePtr frame, const denoise::SessionOptions& options,
                        const denoise::ProgressFn& progress) {
    if (!options.prefilter) return frame;
    return std::make_shared<const FrameBuffers>(
        denoise::prefilterFeatures(*frame, options.prefilterParams, progress));
}

denoise::Session buildSession(FramePtr frame, FramePtr filterInput,
                              const denoise::SessionOptions& options,
                              const std::vector<denoise::LayerSpec>& carry,
                              const std::vector<Image>& carryWeights,
                              const std::vector<std::string>& carryNames,
                              const denoise::ProgressFn& progress) {
    denoise::Session session(*frame, options);
    for (std::size_t i = 0; i < carry.size(); ++i) {
        if (const auto& c = carry[i].correction) {
            session.addCorrection(c->result, c->blend);  // auto's correction, as it was
        } else {
            const denoise::Filter& f = denoise::findFilter(carry[i].filter);
            Image output =
                denoise::applyFilter(f, *filterInput, carry[i].params,
                                     {.region = std::nullopt, .progress = progress, .threads = 0});
            session.addLayer(carry[i].filter, carry[i].params, std::move(output));
        }
        if (i < carryWeights.size()) session.setWeights(session.layerCount() - 1, carryWeights[i]);
        if (i < carryNames.size()) session.renameLayer(session.layerCount() - 1, carryNames[i]);
    }
    return session;
}

Reapplied computeReapply(FramePtr frame, const denoise::Session::Snapshot& snapshot,
                         const denoise::ProgressFn& progress) {
    // The filters' input, each layer's output, the session's own copy of the render (about
    // 100 MB at 1024², features included) and its composite under the snapshot's weights:
    // installing them on the UI thread is moves and pointer swaps.
    Reapplied out;
    out.filterInput = filterInputFor(frame, snapshot.options);
    std::vector<Image> outputs;
    for (const denoise::LayerSpec& spec : snapshot.specs)
        outputs.push_back(
            denoise::applyFilter(denoise::findFilter(spec.filter), *out.filterInput, spec.params,
                                 {.region = std::nullopt, .progress = progress, .threads = 0}));
    // The session keeps its own copy of the prefiltered features: copied, not prefiltered again.
    out.prepared =
        std::make_shared<denoise::Session::Reapplication>(denoise::Session::prepareReapply(
            *frame, std::move(outputs), snapshot,
            snapshot.options.prefilter ? std::optional<FrameBuffers>(*out.filterInput)
                                       : std::nullopt));
    return out;
}

}  // namespace glint::studio
