// The journal's JSON (docs/studio.md, "Autosave"): each session operation as the JSON object one
// journal line holds, and back. SessionAdapter records typed operations and the recovery
// (model/recovery.h) replays them; only this file knows their keys.
#pragma once

#include <QJsonObject>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "glint/denoise/paint.h"
#include "glint/denoise/session.h"
#include "glint/render/settings.h"
#include "model/reference_info.h"

namespace glint::studio::journal_codec {

/// A session started on a render (the entry's frame), with `layers` carried over (their weights
/// are the entry's images, then the corrections' images: correctionImages).
struct Start {
    denoise::SessionOptions options;
    std::vector<denoise::LayerSpec> layers;
    std::vector<std::string> names;  ///< the first layers' own names ("": none); may be shorter
    /// The bank folder the session names (Session::bankDir: its filters' fixed parameters are the
    /// studio's banks'); "" when none.
    std::string bankDir;
};
/// A new render as the session's input (the entry's frame).
struct Input {};
/// A layer added; `fill`: filled with the entry's first image as its mask.
struct AddLayer {
    std::string filter;
    denoise::ParamValues params;
    bool fill = false;
};
/// Layers added with their weights (the entry's images, in order, then the corrections' images:
/// correctionImages) as one undo step: what Auto Start made.
struct AddLayers {
    std::vector<denoise::LayerSpec> layers;
};
struct RemoveLayer {
    std::size_t index = 0;
};
/// Layer `index` renamed (an empty name: named after its filter again).
struct RenameLayer {
    std::size_t index = 0;
    std::string name;
};
/// Layer `index`'s weights set to the entry's first image.
struct Weights {
    std::size_t index = 0;
};
/// Layer `index` filled through the entry's first image as a mask.
struct Fill {
    std::size_t index = 0;
    denoise::BrushMode mode = denoise::BrushMode::Add;
};
/// A brush stroke: its dabs' centres as x, y pairs.
struct Stroke {
    std::size_t layer = 0;
    denoise::Brush brush;
    denoise::BrushMode mode = denoise::BrushMode::Add;
    std::vector<double> dabs;
};
/// The weights of `layers` set to the entry's images, in order (a Poisson diffusion's result).
struct Apply {
    std::vector<std::size_t> layers;
};
/// The session dropped (a new file opens, File > New Session).
struct Clear {};
struct Undo {};
struct Redo {};

using Op = std::variant<Start, Input, AddLayer, AddLayers, RemoveLayer, RenameLayer, Weights, Fill,
                        Stroke, Apply, Clear, Undo, Redo>;

/// The images a Start or AddLayers entry holds after one weight map per layer: the result and
/// the blend of each of `layers` that is auto's correction (LayerSpec::correction), in order.
std::vector<Image> correctionImages(const std::vector<denoise::LayerSpec>& layers);
/// Gives each of `layers` named kAutoCorrection its correction from `images` (one weight map per
/// layer, then correctionImages). Throws glint::Error(Format) when an image is missing.
void takeCorrections(std::vector<denoise::LayerSpec>& layers, const std::vector<Image>& images);

/// The JSON of `op`.
QJsonObject encode(const Op& op);
/// The operation a journal line's JSON holds. Throws glint::Error(Format) naming an unknown
/// operation.
Op decode(const QJsonObject& json);

/// The render settings the user chose (userSettingNames: spp, seed, integrator, MIS, half
/// buffers) as a journal line of their own ("op": "settings", the settings codec's names and
/// text, as a session file's view state holds them).
QJsonObject encodeSettings(const render::Settings& settings);
/// `settings` with what a "settings" line says (missing keys leave the value). Read strictly
/// (readSettings): a bad value throws glint::Error(Format) naming `file` and `where` (the line)
/// with the key.
render::Settings decodeSettings(const QJsonObject& json, render::Settings settings,
                                const std::string& file = {}, const std::string& where = {});

/// The document's reference as a journal line of its own ("op": "reference", the keys a session
/// file's view state describes it with; none: the reference was cleared). A rendered
/// reference's pixels are the entry's frame.
QJsonObject encodeReference(const std::optional<ReferenceInfo>& info);
/// What a "reference" line says (nullopt: cleared); `look` is the scene's look now
/// (readReferenceState).
std::optional<ReferenceInfo> decodeReference(const QJsonObject& json,
                                             const std::vector<render::LookItem>& look);

/// The region of interest as a journal line of its own ("op": "region", not an undo step): the
/// lasso's points as x, y pairs in image pixels; none: the whole image.
QJsonObject encodeRegion(const std::vector<double>& lasso);
/// The lasso a "region" line holds (x, y pairs; empty: the whole image). Throws
/// glint::Error(Format) unless it is an even number of finite numbers.
std::vector<double> decodeRegion(const QJsonObject& json);

/// The view a session file keeps besides the region: the viewer's exposure (stops),
/// Render ▸ Keep Refining, the stage (0 Features … 3 Paint) and the channel the viewer shows.
struct View {
    double exposure = 0.0;
    bool keepRefining = false;
    std::optional<int> stage;  ///< none in journals written before the stage was kept
    /// The viewer's channel by its key (views/viewer.h, channelKey); none in journals written
    /// before the channel was kept. The viewer, not this codec, knows which names are channels.
    std::optional<std::string> channel;
    bool operator==(const View&) const = default;
};
/// The stages a view can name: 0 … kStages - 1.
inline constexpr int kStages = 4;
/// The view as a journal line of its own ("op": "view", not an undo step).
QJsonObject encodeView(const View& view);
/// What a "view" line says. Throws glint::Error(Format) unless the exposure is a finite number,
/// Keep Refining true or false, the stage (when there is one) an integer in [0, kStages) and the
/// channel (when there is one) a string.
View decodeView(const QJsonObject& json);

/// One look property given a value without an undo step ("op": "setLook"): what opening a session
/// file applies to its scene's look, and what a restore applies.
QJsonObject encodeSetLook(const std::string& item, const std::string& property,
                          const std::array<double, 3>& value);

}  // namespace glint::studio::journal_codec
