// What a session file keeps of the document besides the painting (docs/studio.md, "Session
// files"): the look as edited and the render settings the user chose, as the string keys of the
// session's view state. Older session files lack some of these keys: what is missing keeps the
// scene's own value. No widgets here.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "glint/render/look.h"
#include "glint/render/settings.h"

namespace glint::studio {

class Document;

/// The view-state key of one look property: "look/<item>/<property>".
std::string lookKey(const std::string& item, const std::string& property);

/// The render settings a user chooses in the studio (the render bar), by their names in the
/// settings codec (glint/render/settings_codec.h): "spp", "seed", "integrator", "mis",
/// "halfBuffers".
const std::vector<std::string>& userSettingNames();

/// Adds every look property (as "look/<item>/<property>" = "r g b") and the user's render
/// settings (userSettingNames, as the settings codec writes them) to `state`.
void writeDocumentState(const std::vector<render::LookItem>& look, const render::Settings& settings,
                        std::map<std::string, std::string>& state);

/// `settings` with what `state` says of the user's render settings (userSettingNames; missing
/// keys leave the value as it is; "halves" = "0" / "1", as files written before the settings
/// codec say "halfBuffers"). Read strictly by the settings codec, with the renderer's limits
/// (spp 1…2^24, seed 0…2^63−1): a bad value throws glint::Error(Format) naming `file`, the place
/// `pointer` + key (e.g. "/view/spp") and what was expected.
render::Settings readSettings(const std::map<std::string, std::string>& state,
                              render::Settings settings, const std::string& file = {},
                              const std::string& pointer = {});

/// `look` with the values `state` holds under "look/<item>/<property>" (values that are missing
/// or unreadable keep those of `look`).
std::vector<render::LookItem> readLook(const std::map<std::string, std::string>& state,
                                       std::vector<render::LookItem> look);

/// Applies the look values `state` holds to `document` without rendering; properties the scene
/// does not have, or values it refuses, are skipped and named in the result ("" when none).
std::string applyLook(const std::map<std::string, std::string>& state, Document& document);

}  // namespace glint::studio
