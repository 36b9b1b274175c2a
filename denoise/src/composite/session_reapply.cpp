// Re-applying a session's layers to a new render: the outputs every layer (current or in the
// undo history) needs, computed here or elsewhere, and the prepared form a program builds on a
// worker thread so that installing it is moves and pointer swaps.
#include "composite/session_impl.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

bool sameSpec(const LayerSpec& a, const SessionLayer& b) {
    return a.filter == b.filter && a.params == b.params;
}

}  // namespace

std::vector<LayerSpec> Session::layerSpecs() const {
    const Impl& s = *m_impl;
    std::vector<LayerSpec> specs;
    auto add = [&](const SessionLayer& l) {
        for (const LayerSpec& known : specs)
            if (sameSpec(known, l)) return;
        specs.emplace_back(l.filter, l.params);
    };
    // Auto's correction has no filter to run: it is no spec.
    for (const SessionLayer& l : s.layers)
        if (!l.correction) add(l);
    for (const auto* history : {&s.undo, &s.redo})
        for (const SessionEdit& e : *history)
            if (e.kind != SessionEdit::Kind::Weights && !e.layer.correction) add(e.layer);
    return specs;
}

namespace {

// The filters' input for a render: its features prefiltered when the options say so (nothing
// otherwise: the filters read the render itself).
std::optional<FrameBuffers> prefilteredFor(const FrameBuffers& input,
                                           const SessionOptions& options) {
    if (!options.prefilter) return std::nullopt;
    return prefilterFeatures(input, options.prefilterParams);
}

// The outputs of `layers` on a filter input, progress shared out evenly.
std::vector<Image> outputsOn(const FrameBuffers& in, const std::vector<LayerSpec>& layers,
                             const ProgressFn& progress) {
    std::vector<Image> outputs;
    const std::size_t n = layers.size();
    for (std::size_t i = 0; i < n; ++i) {
        ProgressFn part;
        if (progress) part = [&, i](double f) { return progress((double(i) + f) / double(n)); };
        // A layer that cannot run here (an external program not allowed) stays the input.
        if (!findFilter(layers[i].filter).unavailable(layers[i].params).empty())
            outputs.push_back(in.color());
        else
            outputs.push_back(runLayerFilter(in, layers[i].filter, layers[i].params, part));
    }
    return outputs;
}

// Shares each output (moved, not copied).
std::vector<std::shared_ptr<const Image>> shareAll(std::vector<Image>& outputs) {
    std::vector<std::shared_ptr<const Image>> shared;
    shared.reserve(outputs.size());
    for (Image& o : outputs) shared.push_back(std::make_shared<const Image>(std::move(o)));
    return shared;
}

// Refuses outputs that are not one frame-sized colour image per spec.
void checkOutputs(const std::vector<Image>& outputs, std::size_t specs, int width, int height) {
    if (outputs.size() != specs)
        throw Error(ErrorKind::InvalidArgument,
                    "reapply needs one output per entry of layerSpecs() (" + std::to_string(specs) +
                        "), got " + std::to_string(outputs.size()),
                    {}, "session");
    for (const Image& o : outputs)
        if (o.width() != width || o.height() != height || o.channels() != 3)
            throw Error(ErrorKind::InvalidArgument,
                        "a layer output must be " + std::to_string(width) + "x" +
                            std::to_string(height) + "x3",
                        {}, "session");
}

}  // namespace

std::vector<Image> Session::computeOutputs(const FrameBuffers& input, const SessionOptions& options,
                                           const std::vector<LayerSpec>& layers,
                                           const ProgressFn& progress) {
    const std::optional<FrameBuffers> prefiltered = prefilteredFor(input, options);
    return outputsOn(prefiltered ? *prefiltered : input, layers, progress);
}

void Session::Impl::checkSameSize(const FrameBuffers& newInput) const {
    if (newInput.width() != input.width() || newInput.height() != input.height())
        throw Error(ErrorKind::InvalidArgument,
                    "the new render is " + std::to_string(newInput.width()) + "x" +
                        std::to_string(newInput.height()) + ", the session " +
                        std::to_string(input.width()) + "x" + std::to_string(input.height()),
                    {}, "session");
}

void Session::Impl::install(FrameBuffers newInput, std::optional<FrameBuffers> newPrefiltered,
                            const std::vector<LayerSpec>& specs,
                            const std::vector<std::shared_ptr<const Image>>& outputs) {
    input = std::move(newInput);
    prefiltered = std::move(newPrefiltered);
    // Current layers and the layers the history would bring back share the new outputs; a layer
    // that could not run before (a program allowed since) says so no longer.
    auto refresh = [&](SessionLayer& l) {
        if (l.correction) return;  // nothing to re-run: the correction is carried over
        for (std::size_t k = 0; k < specs.size(); ++k)
            if (sameSpec(specs[k], l)) l.output = outputs[k];
        l.unavailable = findFilter(l.filter).unavailable(l.params);
    };
    for (SessionLayer& l : layers) refresh(l);
    for (auto* history : {&undo, &redo})
        for (SessionEdit& e : *history)
            if (e.kind != SessionEdit::Kind::Weights) refresh(e.layer);
    ++version;
}

void Session::reapply(FrameBuffers newInput, const ProgressFn& progress) {
    Impl& s = *m_impl;
    s.checkSameSize(newInput);
    // Everything is computed before anything changes: an error or a stop leaves the session.
    const std::vector<LayerSpec> specs = layerSpecs();
    std::optional<FrameBuffers> prefiltered = prefilteredFor(newInput, s.options);
    std::vector<Image> outputs = outputsOn(prefiltered ? *prefiltered : newInput, specs, progress);
    if (s.stroking) endStroke();
    s.install(std::move(newInput), std::move(prefiltered), specs, shareAll(outputs));
    s.recomposite(s.composite.bounds());
}

void Session::reapply(FrameBuffers newInput, std::vector<Image> outputs) {
    Impl& s = *m_impl;
    s.checkSameSize(newInput);
    const std::vector<LayerSpec> specs = layerSpecs();
    checkOutputs(outputs, specs.size(), width(), height());
    std::optional<FrameBuffers> prefiltered = prefilteredFor(newInput, s.options);
    if (s.stroking) endStroke();
    s.install(std::move(newInput), std::move(prefiltered), specs, shareAll(outputs));
    s.recomposite(s.composite.bounds());
}

Session::Snapshot Session::snapshot() const {
    const Impl& s = *m_impl;
    Snapshot snap;
    snap.options = s.options;
    snap.specs = layerSpecs();
    for (const SessionLayer& l : s.layers) {
        std::size_t k = 0;
        // layerSpecs() lists every current layer but auto's correction.
        if (l.correction)
            k = snap.specs.size();
        else
            while (!sameSpec(snap.specs[k], l)) ++k;
        snap.uses.push_back(k);
        snap.corrections.push_back(l.correction);
        snap.weights.push_back(l.weights);
    }
    snap.version = s.version;
    return snap;
}

Session::Reapplication Session::prepareReapply(FrameBuffers newInput, std::vector<Image> outputs,
                                               const Snapshot& snapshot) {
    checkOutputs(outputs, snapshot.specs.size(), newInput.width(), newInput.height());
    Reapplication r;
    r.filterInput = prefilteredFor(newInput, snapshot.options);
    r.specs = snapshot.specs;
    r.outputs = shareAll(outputs);
    r.version = snapshot.version;
    // The composite as Impl::recomposite builds it, under the snapshot's weights.
    r.composite = newInput.color();
    for (std::size_t i = 0; i < snapshot.uses.size(); ++i) {
        const SessionCorrection* correction =
            i < snapshot.corrections.size() ? snapshot.corrections[i].get() : nullptr;
        composeLayer(r.composite, correction ? nullptr : r.outputs[snapshot.uses[i]].get(),
                     correction, snapshot.weights[i], r.composite.bounds());
    }
    r.input = std::move(newInput);
    return r;
}

void Session::reapply(Reapplication prepared) {
    Impl& s = *m_impl;
    s.checkSameSize(prepared.input);
    const std::vector<LayerSpec> specs = layerSpecs();
    bool same = specs.size() == prepared.specs.size();
    for (std::size_t k = 0; same && k < specs.size(); ++k)
        same = specs[k].filter == prepared.specs[k].filter &&
               specs[k].params == prepared.specs[k].params;
    if (!same)
        throw Error(ErrorKind::InvalidArgument,
                    "the prepared re-application is of other layers than the session's", {},
                    "session");
    if (s.stroking) endStroke();
    const bool current = prepared.version == s.version;
    s.install(std::move(prepared.input), std::move(prepared.filterInput), specs, prepared.outputs);
    // The weights changed since the snapshot: the composite is built again here.
    if (current)
        std::swap(s.composite, prepared.composite);
    else
        s.recomposite(s.composite.bounds());
}

}  // namespace glint::denoise
