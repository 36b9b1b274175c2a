// The private state of a painting session, shared by session.cpp (edits, undo, re-application)
// and session_io.cpp (save, load, export).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "glint/denoise/session.h"

namespace glint::denoise {

/// Weights and painted masks of one layer over a rectangle, before and after an edit.
struct WeightsChange {
    std::size_t layer = 0;
    Rect rect;
    Image weightsBefore, paintedBefore, weightsAfter, paintedAfter;
};

/// One undo step.
struct SessionEdit {
    enum class Kind { AddLayer, RemoveLayer, Weights, Rename };
    Kind kind = Kind::Weights;
    std::size_t index = 0;               // AddLayer / RemoveLayer / Rename: the layer's position
    SessionLayer layer;                  // AddLayer / RemoveLayer: the layer itself
    std::vector<WeightsChange> changes;  // Weights
    std::string nameBefore, nameAfter;   // Rename

    /// Whether `layer` is set: an added or removed layer (a rename or weights change holds none).
    bool holdsLayer() const { return kind == Kind::AddLayer || kind == Kind::RemoveLayer; }
};

struct Session::Impl {
    FrameBuffers input;
    std::optional<FrameBuffers> prefiltered;  // the filters' input when options.prefilter
    SessionOptions options;
    std::vector<SessionLayer> layers;
    Image composite;
    std::vector<SessionEdit> undo, redo;
    std::uint64_t version = 0;  // counts changes of the layers and weights (Session::version)

    // The open stroke.
    bool stroking = false;
    std::size_t strokeLayer = 0;
    Brush brush;
    BrushMode mode = BrushMode::Add;
    Image strokeWeights, strokePainted;  // the layer's maps when the stroke began
    Image coverage;                      // max of the dabs' brush weights so far
    Rect strokeRect;                     // union of the dabs' rectangles

    const FrameBuffers& filterInput() const { return prefiltered ? *prefiltered : input; }
    /// Rebuilds the composite over `rect` from the input colour through every layer.
    void recomposite(const Rect& rect);
    /// Applies one side of an edit (redo: after, undo: before).
    void apply(const SessionEdit& edit, bool forward);
    /// Records an edit (clears redo).
    void record(SessionEdit edit);
    /// Adds `layer` (filter, output and correction set) on top with weight 0: one undo step.
    /// Returns its index.
    std::size_t pushLayer(SessionLayer layer);
    /// Checks a layer index.
    void checkLayer(std::size_t index) const;
    /// Checks that every index names a layer and none is listed twice.
    void checkDistinctLayers(const std::vector<std::size_t>& indices) const;
    /// Edits other than dabs wait for the open stroke to end.
    void checkNoStroke() const;
    /// Refuses a new render of another size (naming both sizes).
    void checkSameSize(const FrameBuffers& newInput) const;
    /// Makes `newInput` the session's render: `outputs[k]` (on it) becomes the output of every
    /// layer, current or in the history, with the filter and parameters of `specs[k]`. The
    /// composite is left to the caller.
    void install(FrameBuffers newInput, std::optional<FrameBuffers> newPrefiltered,
                 const std::vector<LayerSpec>& specs,
                 const std::vector<std::shared_ptr<const Image>>& outputs);
};

/// Composes one layer into `composite` over `rect`: blends `output` by `weights`, or adds
/// auto's correction when `correction` is set (correctInPlace).
void composeLayer(Image& composite, const Image* output, const SessionCorrection* correction,
                  const Image& weights, const Rect& rect);

/// The filter output of a layer over the whole input (errors name the filter).
Image runLayerFilter(const FrameBuffers& input, const std::string& filter,
                     const ParamValues& params, const ProgressFn& progress);

}  // namespace glint::denoise
