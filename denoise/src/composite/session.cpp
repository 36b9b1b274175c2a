// The painting session: layers, the composite, strokes, fills, diffusion, undo and redo, and
// re-applying the layers to a new render (session_reapply.h). Session files: session_io.cpp.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "composite/correction.h"
#include "composite/session_impl.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/composite.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {

Rect unite(const Rect& a, const Rect& b) {
    if (a.empty()) return b;
    if (b.empty()) return a;
    return {std::min(a.x0, b.x0), std::max(a.x1, b.x1), std::min(a.y0, b.y0), std::max(a.y1, b.y1)};
}

// Writes `crop` (of rect's size) into `image` at rect.
void put(Image& image, const Image& crop, const Rect& rect) {
    paste(image, crop, rect.x0, rect.y0);
}

}  // namespace

void composeLayer(Image& composite, const Image* output, const SessionCorrection* correction,
                  const Image& weights, const Rect& rect) {
    if (correction)
        correctInPlace(composite, *correction, weights, rect);
    else
        blendInPlace(composite, *output, weights, rect);
}

Image runLayerFilter(const FrameBuffers& input, const std::string& filter,
                     const ParamValues& params, const ProgressFn& progress) {
    FilterOptions options;
    options.progress = progress;
    return applyFilter(findFilter(filter), input, params, options);
}

void Session::Impl::recomposite(const Rect& rect) {
    const Rect r = intersect(rect, composite.bounds());
    if (r.empty()) return;
    // Band by band, so that a band stays in cache through every layer, bands in parallel for a
    // large rectangle (a whole frame after an undo or a reapply); the same operations per pixel
    // as blending layer after layer over the whole rectangle, so the same bits.
    const Image& color = input.color();
    const std::size_t rowBytes = std::size_t(r.x1 - r.x0) * std::size_t(composite.channels());
    auto band = [&](int y0, int y1) {
        for (int y = y0; y < y1; ++y)
            std::copy_n(color.row(y) + std::size_t(r.x0) * std::size_t(color.channels()), rowBytes,
                        composite.row(y) + std::size_t(r.x0) * std::size_t(color.channels()));
        for (const SessionLayer& layer : layers)
            composeLayer(composite, layer.output.get(), layer.correction.get(), layer.weights,
                         Rect{r.x0, r.x1, y0, y1});
    };
    constexpr int kBandRows = 16;
    if (std::int64_t(r.x1 - r.x0) * (r.y1 - r.y0) < 256 * 256) {
        band(r.y0, r.y1);  // a dab: not worth the threads
        return;
    }
    tbb::parallel_for(tbb::blocked_range<int>(r.y0, r.y1, kBandRows),
                      [&](const tbb::blocked_range<int>& rows) { band(rows.begin(), rows.end()); });
}

void Session::Impl::checkLayer(std::size_t index) const {
    if (index >= layers.size())
        throw Error(ErrorKind::InvalidArgument,
                    "layer " + std::to_string(index) + " does not exist (the session has " +
                        std::to_string(layers.size()) + ")",
                    {}, "session");
}

void Session::Impl::checkDistinctLayers(const std::vector<std::size_t>& indices) const {
    for (std::size_t k = 0; k < indices.size(); ++k) {
        checkLayer(indices[k]);
        for (std::size_t j = 0; j < k; ++j)
            if (indices[j] == indices[k])
                throw Error(ErrorKind::InvalidArgument,
                            "layer " + std::to_string(indices[k]) + " is listed twice", {},
                            "session");
    }
}

void Session::Impl::checkNoStroke() const {
    if (stroking)
        throw Error(ErrorKind::InvalidArgument, "a stroke is open (endStroke first)", {},
                    "session");
}

void Session::Impl::apply(const SessionEdit& edit, bool forward) {
    ++version;
    switch (edit.kind) {
        case SessionEdit::Kind::AddLayer:
        case SessionEdit::Kind::RemoveLayer: {
            const bool insert = (edit.kind == SessionEdit::Kind::AddLayer) == forward;
            if (insert)
                layers.insert(layers.begin() + std::ptrdiff_t(edit.index), edit.layer);
            else
                layers.erase(layers.begin() + std::ptrdiff_t(edit.index));
            recomposite(composite.bounds());
            return;
        }
        case SessionEdit::Kind::Weights:
            for (const WeightsChange& c : edit.changes) {
                SessionLayer& layer = layers[c.layer];
                put(layer.weights, forward ? c.weightsAfter : c.weightsBefore, c.rect);
                put(layer.painted, forward ? c.paintedAfter : c.paintedBefore, c.rect);
                recomposite(c.rect);
            }
            return;
        case SessionEdit::Kind::Rename:
            layers[edit.index].name = forward ? edit.nameAfter : edit.nameBefore;
            return;
    }
}

void Session::Impl::record(SessionEdit edit) {
    undo.push_back(std::move(edit));
    redo.clear();
}

Session::Session(FrameBuffers input, const SessionOptions& options)
    : m_impl(std::make_unique<Impl>()) {
    if (input.width() <= 0 || input.height() <= 0 || !input.has(Layer::Color))
        throw Error(ErrorKind::InvalidArgument, "a session needs a frame with a colour layer", {},
                    "session");
    m_impl->options = options;
    m_impl->options.prefilterParams =
        resolveParams(prefilterParams(), options.prefilterParams, "feature prefilter");
    if (options.prefilter) m_impl->prefiltered = prefilterFeatures(input, options.prefilterParams);
    m_impl->composite = input.color();
    m_impl->input = std::move(input);
}

Session::~Session() = default;
Session::Session(Session&&) noexcept = default;
Session& Session::operator=(Session&&) noexcept = default;

const FrameBuffers& Session::input() const {
    return m_impl->input;
}
const FrameBuffers& Session::filterInput() const {
    return m_impl->filterInput();
}
const SessionOptions& Session::options() const {
    return m_impl->options;
}
int Session::width() const {
    return m_impl->input.width();
}
int Session::height() const {
    return m_impl->input.height();
}
std::size_t Session::layerCount() const {
    return m_impl->layers.size();
}
const SessionLayer& Session::layer(std::size_t index) const {
    m_impl->checkLayer(index);
    return m_impl->layers[index];
}
const Image& Session::composite() const {
    return m_impl->composite;
}
std::uint64_t Session::version() const {
    return m_impl->version;
}

std::size_t Session::addLayer(const std::string& filter, const ParamValues& params,
                              std::optional<Image> output, const ProgressFn& progress) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    const Filter& f = findFilter(filter);
    SessionLayer layer;
    layer.filter = std::string(f.name());
    layer.params = resolveParams(f, params);
    if (output) {
        if (output->width() != width() || output->height() != height() || output->channels() != 3)
            throw Error(ErrorKind::InvalidArgument,
                        "a layer's output must be " + std::to_string(width()) + "x" +
                            std::to_string(height()) + "x3",
                        {}, "session");
        layer.output = std::make_shared<const Image>(std::move(*output));
    } else {
        layer.output = std::make_shared<const Image>(
            runLayerFilter(s.filterInput(), layer.filter, layer.params, progress));
    }
    return s.pushLayer(std::move(layer));
}

std::size_t Session::addCorrection(Image result, std::optional<Image> blend) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    auto correction = std::make_shared<SessionCorrection>();
    correction->result = std::move(result);
    correction->blend = blend ? std::move(*blend) : s.composite;
    const std::string problem = correctionProblem(*correction, width(), height());
    if (!problem.empty())
        throw Error(ErrorKind::InvalidArgument, "auto's correction: " + problem, {}, "session");
    SessionLayer layer;
    layer.filter = kAutoCorrection;
    // The layer's output is auto's result (what it shows over the blend it corrected), shared
    // with the correction.
    layer.output = std::shared_ptr<const Image>(correction, &correction->result);
    layer.correction = std::move(correction);
    return s.pushLayer(std::move(layer));
}

std::size_t Session::Impl::pushLayer(SessionLayer layer) {
    const int w = input.width(), h = input.height();
    layer.weights = Image(w, h, 1, 0.0f);
    layer.painted = Image(w, h, 1, 0.0f);
    SessionEdit edit;
    edit.kind = SessionEdit::Kind::AddLayer;
    edit.index = layers.size();
    edit.layer = layer;
    layers.push_back(std::move(layer));  // weight 0: the composite does not change
    ++version;
    record(std::move(edit));
    return layers.size() - 1;
}

void Session::removeLayer(std::size_t index) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    s.checkLayer(index);
    SessionEdit edit;
    edit.kind = SessionEdit::Kind::RemoveLayer;
    edit.index = index;
    edit.layer = s.layers[index];
    s.apply(edit, true);
    s.record(std::move(edit));
}

void Session::renameLayer(std::size_t index, const std::string& name) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    s.checkLayer(index);
    if (s.layers[index].name == name) return;
    SessionEdit edit;
    edit.kind = SessionEdit::Kind::Rename;
    edit.index = index;
    edit.nameBefore = s.layers[index].name;
    edit.nameAfter = name;
    s.apply(edit, true);
    s.record(std::move(edit));
}

void Session::setWeights(std::size_t index, const Image& weights) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    s.checkLayer(index);
    if (weights.width() != width() || weights.height() != height() || weights.channels() != 1)
        throw Error(
            ErrorKind::InvalidArgument,
            "weights must be " + std::to_string(width()) + "x" + std::to_string(height()) + "x1",
            {}, "session");
    SessionLayer& layer = s.layers[index];
    // The maps before move into the undo step; the layer gets copies of those after (two
    // frame-sized copies fewer than applying the step).
    WeightsChange c{index,
                    layer.weights.bounds(),
                    std::move(layer.weights),
                    std::move(layer.painted),
                    weights,
                    Image(width(), height(), 1, 1.0f)};
    for (float& v : c.weightsAfter.data()) v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
    layer.weights = c.weightsAfter;
    layer.painted = c.paintedAfter;
    ++s.version;
    s.recomposite(c.rect);
    SessionEdit edit;
    edit.changes.push_back(std::move(c));
    s.record(std::move(edit));
}

void Session::beginStroke(std::size_t layer, const Brush& brush, BrushMode mode) {
    Impl& s = *m_impl;
    if (s.stroking)
        throw Error(ErrorKind::InvalidArgument, "a stroke is already open", {}, "session");
    s.checkLayer(layer);
    validate(brush);
    s.stroking = true;
    s.strokeLayer = layer;
    s.brush = brush;
    s.mode = mode;
    s.strokeWeights = s.layers[layer].weights;
    s.strokePainted = s.layers[layer].painted;
    s.coverage = Image(width(), height(), 1, 0.0f);
    s.strokeRect = {};
}

Rect Session::dab(double x, double y) {
    Impl& s = *m_impl;
    if (!s.stroking)
        throw Error(ErrorKind::InvalidArgument, "no stroke is open (beginStroke first)", {},
                    "session");
    if (!std::isfinite(x) || !std::isfinite(y))
        throw Error(ErrorKind::InvalidArgument, "a dab position must be finite", {}, "session");
    const Rect r = dabRect(x, y, s.brush, width(), height());
    if (r.empty()) return r;
    SessionLayer& layer = s.layers[s.strokeLayer];
    const float sign = s.mode == BrushMode::Add ? 1.0f : -1.0f;
    for (int py = r.y0; py < r.y1; ++py)
        for (int px = r.x0; px < r.x1; ++px) {
            const double dx = px + 0.5 - x, dy = py + 0.5 - y;
            const float wgt = brushWeight(std::sqrt(dx * dx + dy * dy), s.brush);
            float& cov = s.coverage(px, py, 0);
            if (wgt <= cov) continue;
            cov = wgt;
            // The stroke's coverage against the weight before the stroke: overlapping dabs of
            // one stroke do not pile up.
            layer.weights(px, py, 0) =
                std::clamp(s.strokeWeights(px, py, 0) + sign * cov, 0.0f, 1.0f);
            layer.painted(px, py, 0) = 1.0f;
        }
    s.strokeRect = unite(s.strokeRect, r);
    ++s.version;
    s.recomposite(r);
    return r;
}

void Session::endStroke() {
    Impl& s = *m_impl;
    if (!s.stroking) return;
    s.stroking = false;
    if (s.strokeRect.empty()) return;
    const SessionLayer& layer = s.layers[s.strokeLayer];
    WeightsChange c{s.strokeLayer,
                    s.strokeRect,
                    s.strokeWeights.crop(s.strokeRect),
                    s.strokePainted.crop(s.strokeRect),
                    layer.weights.crop(s.strokeRect),
                    layer.painted.crop(s.strokeRect)};
    SessionEdit edit;
    edit.changes.push_back(std::move(c));
    s.record(std::move(edit));
    s.strokeWeights = Image();
    s.strokePainted = Image();
    s.coverage = Image();
}

bool Session::inStroke() const {
    return m_impl->stroking;
}

Rect Session::fill(std::size_t index, const Image& mask, BrushMode mode) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    s.checkLayer(index);
    if (mask.width() != width() || mask.height() != height() || mask.channels() != 1)
        throw Error(ErrorKind::InvalidArgument, "the fill mask must match the frame (1 channel)",
                    {}, "session");
    Rect box;
    for (int y = 0; y < height(); ++y)
        for (int x = 0; x < width(); ++x)
            if (mask(x, y, 0) > 0.0f) box = unite(box, Rect{x, x + 1, y, y + 1});
    if (box.empty()) return box;
    SessionLayer& layer = s.layers[index];
    WeightsChange c{index, box, layer.weights.crop(box), layer.painted.crop(box), {}, {}};
    c.weightsAfter = c.weightsBefore;
    c.paintedAfter = c.paintedBefore;
    for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x)
            if (mask(x, y, 0) > 0.0f) {
                c.weightsAfter(x - box.x0, y - box.y0, 0) = mode == BrushMode::Add ? 1.0f : 0.0f;
                c.paintedAfter(x - box.x0, y - box.y0, 0) = 1.0f;
            }
    SessionEdit edit;
    edit.changes.push_back(std::move(c));
    s.apply(edit, true);
    s.record(std::move(edit));
    return box;
}

std::vector<Image> Session::diffusionMaps(const std::vector<std::size_t>& indices,
                                          const DiffusionOptions& options) const {
    const Impl& s = *m_impl;
    if (indices.empty())
        throw Error(ErrorKind::InvalidArgument, "no layer to diffuse", {}, "session");
    s.checkDistinctLayers(indices);
    // Every listed layer's painted pixels, and whose they are.
    Image anyPainted(width(), height(), 1, 0.0f);
    for (std::size_t i : indices) {
        bool painted = false;
        for (std::size_t p = 0; p < anyPainted.pixelCount(); ++p)
            if (s.layers[i].painted.data()[p] > 0.0f) {
                anyPainted.data()[p] = 1.0f;
                painted = true;
            }
        if (!painted)
            throw Error(ErrorKind::InvalidArgument,
                        "layer " + std::to_string(i) + " has no painted pixel to diffuse from", {},
                        "session");
    }
    // One map per layer: its own painted pixels keep their weights, the other listed layers'
    // painted pixels are 0 for it; everything else is solved for.
    std::vector<Image> maps;
    for (std::size_t i : indices) {
        const SessionLayer& layer = s.layers[i];
        Image values(width(), height(), 1, 0.0f);
        for (std::size_t p = 0; p < values.pixelCount(); ++p)
            values.data()[p] = layer.painted.data()[p] > 0.0f ? layer.weights.data()[p] : 0.0f;
        maps.push_back(diffuseWeights(values, anyPainted, options));
    }
    return maps;
}

void Session::applyWeights(const std::vector<std::size_t>& indices,
                           const std::vector<Image>& maps) {
    Impl& s = *m_impl;
    s.checkNoStroke();
    if (indices.size() != maps.size())
        throw Error(ErrorKind::InvalidArgument, "one weight map per layer", {}, "session");
    s.checkDistinctLayers(indices);
    SessionEdit edit;
    for (std::size_t k = 0; k < indices.size(); ++k) {
        const Image& map = maps[k];
        if (map.width() != width() || map.height() != height() || map.channels() != 1)
            throw Error(ErrorKind::InvalidArgument, "a weight map must match the frame (1 channel)",
                        {}, "session");
        const SessionLayer& layer = s.layers[indices[k]];
        WeightsChange c{indices[k], layer.weights.bounds(), layer.weights, layer.painted,
                        map,        layer.painted};
        for (float& v : c.weightsAfter.data())
            v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
        edit.changes.push_back(std::move(c));
    }
    s.apply(edit, true);
    s.record(std::move(edit));
}

void Session::diffuse(const std::vector<std::size_t>& indices, const DiffusionOptions& options) {
    m_impl->checkNoStroke();
    applyWeights(indices, diffusionMaps(indices, options));
}

bool Session::canUndo() const {
    return !m_impl->undo.empty() && !m_impl->stroking;
}
bool Session::canRedo() const {
    return !m_impl->redo.empty() && !m_impl->stroking;
}

void Session::undo() {
    Impl& s = *m_impl;
    if (!canUndo()) return;
    SessionEdit edit = std::move(s.undo.back());
    s.undo.pop_back();
    s.apply(edit, false);
    s.redo.push_back(std::move(edit));
}

void Session::redo() {
    Impl& s = *m_impl;
    if (!canRedo()) return;
    SessionEdit edit = std::move(s.redo.back());
    s.redo.pop_back();
    s.apply(edit, true);
    s.undo.push_back(std::move(edit));
}

// Re-applying a session's layers to a new render: the outputs every layer (current or in the
// undo history) needs, computed here or elsewhere, and the prepared form a program builds on a
// worker thread so that installing it is moves and pointer swaps.

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
            if (e.holdsLayer() && !e.layer.correction) add(e.layer);
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
            if (e.holdsLayer()) refresh(e.layer);
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
                                               const Snapshot& snapshot,
                                               std::optional<FrameBuffers> filterInput) {
    checkOutputs(outputs, snapshot.specs.size(), newInput.width(), newInput.height());
    if (filterInput &&
        (filterInput->width() != newInput.width() || filterInput->height() != newInput.height()))
        throw Error(ErrorKind::InvalidArgument,
                    "the filter input given is " + std::to_string(filterInput->width()) + "x" +
                        std::to_string(filterInput->height()) + ", the new render " +
                        std::to_string(newInput.width()) + "x" + std::to_string(newInput.height()),
                    {}, "session");
    Reapplication r;
    // The features prefiltered once: the caller's when it made them for the filters.
    r.filterInput = !snapshot.options.prefilter ? std::nullopt
                    : filterInput               ? std::move(filterInput)
                                                : prefilteredFor(newInput, snapshot.options);
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
