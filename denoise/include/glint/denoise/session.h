// The painting and compositing session: an input render, an ordered list of filter layers each
// with a weight map, and the composite built left to right,
//   composite = composite·(1 − w) + filterOutput·w   (starting from the input colour),
// where every filter reads the original input (filters never stack). Strokes, fills and
// Poisson diffusion edit the weight maps; every edit is one undo step; sessions are saved as one
// JSON file plus EXR side files (docs/painting.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/paint.h"
#include "glint/denoise/progress.h"
#include "glint/denoise/session_reapply.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/image/io.h"

namespace glint::denoise {

/// The newest version of the session file this Glint reads. It writes 2 when a layer is auto's
/// correction (the layer kinds of format 2), else 1, which every Glint reads.
inline constexpr int kSessionFormat = 2;

/// SessionLayer::filter of auto's correction layer (no registered filter has this name).
inline constexpr const char* kAutoCorrection = "auto-correction";

/// What auto's correction layer adds (docs/painting.md, "Auto's correction"): auto's result and
/// the composite beneath the layer it corrected. With weight w the layer makes the composite x
///   x + w · (result − blend)   (in double, rounded once, clamped at 0 as the stacking is),
/// and exactly `result` where w = 1 and x is still `blend`, so a session started from auto is
/// auto's result bit for bit.
struct SessionCorrection {
    Image result;  ///< 3 channels, frame-sized, finite
    Image blend;   ///< 3 channels, frame-sized, finite
};

/// One layer: a filter with resolved parameters, its output over the whole frame, and where it
/// shows.
struct SessionLayer {
    std::string filter;  ///< registry name
    ParamValues params;  ///< resolved
    /// The filter applied to the whole input (3 channels). Immutable and shared: copies of the
    /// layer (the undo history, a program's views) share one image.
    std::shared_ptr<const Image> output;
    Image weights;     ///< 1 channel in [0, 1], frame-sized
    Image painted;     ///< 1 channel, 1 where a stroke or fill set the weight (0 elsewhere)
    std::string name;  ///< the user's name for it; empty: a program names it after its filter
    /// Why the filter did not run (Filter::unavailable: an external program the user has not
    /// allowed): the output is then the input colour, so the layer changes nothing. Empty when
    /// it ran.
    std::string unavailable;
    /// Set for auto's correction layer (`filter` is kAutoCorrection, `params` empty, `output`
    /// auto's result): the layer adds its correction to the composite beneath instead of blending
    /// a filter's output over it, and has nothing to re-run on a new render.
    std::shared_ptr<const SessionCorrection> correction;
};

/// Whether a stroke or fill adds weight (left button) or removes it (right button).
enum class BrushMode { Add, Subtract };

class Session {
  public:
    using Snapshot = SessionSnapshot;
    using Reapplication = SessionReapplication;

    /// A session over `input` (with a colour layer), no layers yet. Throws
    /// glint::Error(InvalidArgument) for an empty frame or bad prefilter parameters.
    explicit Session(FrameBuffers input, const SessionOptions& options = {});
    ~Session();
    Session(Session&&) noexcept;
    Session& operator=(Session&&) noexcept;

    /// The input as rendered.
    const FrameBuffers& input() const;
    /// The input as the filters see it (features prefiltered when the options say so).
    const FrameBuffers& filterInput() const;
    const SessionOptions& options() const;
    int width() const;
    int height() const;

    std::size_t layerCount() const;
    const SessionLayer& layer(std::size_t index) const;
    /// The composite colour (3 channels, frame-sized).
    const Image& composite() const;

    /// Adds a layer on top with weight 0 everywhere. Runs the filter over the whole input
    /// unless `output` (frame-sized, 3 channels: e.g. a bank member's whole-frame result) is
    /// given. One undo step. Returns its index. Throws glint::Error for an unknown filter, bad
    /// parameters or a missing layer (nothing changes then), Cancelled when progress says stop.
    std::size_t addLayer(const std::string& filter, const ParamValues& params,
                         std::optional<Image> output = std::nullopt,
                         const ProgressFn& progress = {});
    /// Adds auto's correction on top with weight 0 (SessionCorrection): `result` (3 channels,
    /// frame-sized) against `blend`, by default the composite now. One undo step. Returns its
    /// index. Throws glint::Error(InvalidArgument) for images of the wrong size or non-finite
    /// values (nothing changes then).
    std::size_t addCorrection(Image result, std::optional<Image> blend = std::nullopt);
    /// Removes a layer. One undo step.
    void removeLayer(std::size_t index);
    /// Renames a layer (empty: no name of its own). One undo step; none when the name is the
    /// same. Throws glint::Error(InvalidArgument) for a bad index.
    void renameLayer(std::size_t index, const std::string& name);
    /// Replaces a layer's weights (1 channel, frame-sized, clamped to [0, 1]) and marks every
    /// pixel painted (e.g. "apply everywhere", an automatic start). One undo step.
    void setWeights(std::size_t index, const Image& weights);

    /// Starts a stroke on a layer. Within a stroke the coverage is the maximum of the dabs'
    /// brush weights, and each pixel's weight becomes clamp(weight before the stroke ± coverage,
    /// 0, 1), so overlapping dabs do not pile up. Throws glint::Error(InvalidArgument) for a bad
    /// layer index or brush, or when a stroke is already open.
    void beginStroke(std::size_t layer, const Brush& brush, BrushMode mode);
    /// A dab of the open stroke centred at (x, y) (pixel (i, j) covers [i, i+1) × [j, j+1)).
    /// Updates only the weights and composite pixels inside the dab's rectangle; returns it.
    Rect dab(double x, double y);
    /// Ends the stroke: one undo step (nothing when no dab changed anything).
    void endStroke();
    /// True while a stroke is open.
    bool inStroke() const;

    /// Sets a layer's weights to 1 (Add) or 0 (Subtract) where `mask` (1 channel,
    /// frame-sized, e.g. magicWand's result) is > 0, and marks them painted. One undo step.
    /// Returns the bounding rectangle of the change.
    Rect fill(std::size_t layer, const Image& mask, BrushMode mode);

    /// Poisson-diffusion blending (diffuseWeights): for each of `layers`, its painted pixels
    /// keep their weights, the pixels painted on the other listed layers are fixed at 0, and
    /// every other pixel is solved for, one map per layer. One undo step. Throws
    /// glint::Error(InvalidArgument) when a listed layer has no painted pixel.
    void diffuse(const std::vector<std::size_t>& layers, const DiffusionOptions& options = {});
    /// The maps diffuse() would set, without changing anything (const: a program may compute
    /// them on another thread while nothing edits the session).
    std::vector<Image> diffusionMaps(const std::vector<std::size_t>& layers,
                                     const DiffusionOptions& options = {}) const;
    /// Sets the weights of `layers` to `maps` (clamped to [0, 1]), painted masks unchanged: one
    /// undo step (how diffusion results computed elsewhere are applied).
    void applyWeights(const std::vector<std::size_t>& layers, const std::vector<Image>& maps);

    bool canUndo() const;
    bool canRedo() const;
    /// Undoes the last edit (layer added or removed, weights set, stroke, fill, diffusion).
    void undo();
    void redo();

    /// Re-applies every layer's filter to a new render of the same scene (same size), keeping
    /// the weights: the look changed, the painting stays. The undo history stays too: layers
    /// that edits in it would bring back get their outputs on the new render as well. Throws
    /// glint::Error(InvalidArgument) for another size (nothing changes then).
    void reapply(FrameBuffers newInput, const ProgressFn& progress = {});
    /// The same with the outputs computed elsewhere (computeOutputs, e.g. on a worker thread):
    /// one per entry of layerSpecs(), frame-sized.
    void reapply(FrameBuffers newInput, std::vector<Image> outputs);

    /// Copies what prepareReapply needs (the current layers' weights: small beside the render).
    Snapshot snapshot() const;
    /// Counts the edits of the layers and weights (and undo, redo, reapply): equal versions mean
    /// the same layers with the same weights.
    std::uint64_t version() const;

    /// Everything reapply does that grows with the image, from a snapshot and the outputs on
    /// `newInput` (computeOutputs: one per snapshot spec, frame-sized), touching no session:
    /// safe on a worker thread. `filterInput`: the filters' input the caller already made from
    /// `newInput` when the snapshot's options prefilter (prefilterFeatures with their
    /// parameters), kept instead of prefiltering again. Throws glint::Error(InvalidArgument) for
    /// outputs or a filter input that do not fit.
    static Reapplication prepareReapply(FrameBuffers newInput, std::vector<Image> outputs,
                                        const Snapshot& snapshot,
                                        std::optional<FrameBuffers> filterInput = std::nullopt);
    /// Installs a prepared re-application: moves and pointer swaps only when the session is still
    /// at the snapshot's version (otherwise the composite is rebuilt here). Ends an open stroke.
    /// Throws glint::Error(InvalidArgument) when its specs are no longer layerSpecs() or its size
    /// differs (nothing changes then).
    void reapply(Reapplication prepared);

    /// Every distinct filter and parameter set the session's layers and its undo/redo history
    /// hold (current layers first, in order): what reapply needs outputs for.
    std::vector<LayerSpec> layerSpecs() const;
    /// The outputs of `layers` on `input` (prefiltered as `options` say), as reapply needs them.
    /// Touches no session: safe on a worker thread.
    static std::vector<Image> computeOutputs(const FrameBuffers& input,
                                             const SessionOptions& options,
                                             const std::vector<LayerSpec>& layers,
                                             const ProgressFn& progress = {});

    /// What the studio keeps with a session (saved and loaded, not interpreted here).
    std::optional<Rect> region;                    ///< the region of interest
    std::filesystem::path bankDir;                 ///< the bank cache folder, if any
    std::map<std::string, std::string> viewState;  ///< free-form view settings
    /// Frames kept with the session (a program's reference render, say): each saved as the side
    /// file NAME.exr (NAME: letters, digits and '-', not "input" nor a layer's file) and listed
    /// under "frames" in the session file; loaded back as they were. A file without "frames"
    /// has none.
    std::map<std::string, std::shared_ptr<const FrameBuffers>> sideFrames;

    /// Saves NAME.glint-session.json (with "format") plus the side folder
    /// NAME.glint-session/ holding input.exr, one weights EXR per layer (and correction-N.exr per
    /// correction layer) and the side frames,
    /// written atomically (a failed save leaves the old session intact). Throws
    /// glint::Error(Io), or InvalidArgument for a side frame's name that is no file name.
    void save(const std::filesystem::path& path) const;
    /// Loads a saved session, re-running the layers' filters; a layer whose filter cannot run
    /// here (Filter::unavailable) is loaded without running, marked SessionLayer::unavailable.
    /// Throws glint::Error naming the file: Format for malformed or truncated JSON (with line and
    /// column), a format newer than kSessionFormat or a bad correction layer, Io for a missing
    /// side file.
    static Session load(const std::filesystem::path& path, const ProgressFn& progress = {});

    /// Writes the input's layers with the colour replaced by the composite and the input's colour
    /// kept as the noisy layer (layered EXR; denoisedFrame, metadata denoiseSession).
    void exportExr(const std::filesystem::path& path) const;
    /// Writes an 8-bit PNG of the composite.
    void exportPng(const std::filesystem::path& path, const DisplayOptions& display = {}) const;

    /// Every temporary file or folder a save of a session with `layers` layers to `path`
    /// creates, in the order to remove them (files first): a program interrupted by a signal
    /// removes them (glint::temporaryPathFor names them in advance).
    static std::vector<std::filesystem::path> temporaries(const std::filesystem::path& path,
                                                          std::size_t layers);

  private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

}  // namespace glint::denoise
