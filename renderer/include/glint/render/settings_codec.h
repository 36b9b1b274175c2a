// Render settings as named values: one table of names, kinds, ranges and meanings (settingSpecs)
// from which scene.json's "render" block, the metadata a render records in its EXR
// (glint:<name>), the studio's session files and journal (the same names as text) and
// glint-render's flags (--<name in kebab case>) are read and written. A name is spelt the same
// in all of them.
#pragma once

#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/render/settings.h"

namespace glint::render {

/// What a setting's value is.
enum class SettingKind { Integer, Real, Boolean, Choice };

/// One named field of Settings.
struct SettingSpec {
    const char* name;  ///< the one spelling: scene.json key, glint:<name>, session/journal key
    SettingKind kind;
    std::int64_t lo = 0, hi = 0;  ///< Integer: the range
    double min = 0.0, max = 0.0;  ///< Real: the range
    /// Choice: the names, separated by single spaces ("path mlt").
    const char* choices = "";
    /// Recorded in a rendered frame's metadata: it changes the pixels, so that shards of one
    /// render must agree on it (texture cache and BVH kind do not).
    bool recorded = false;
    const char* meaning = "";  ///< one line, for --help and the docs
};

/// Every named render setting, in the order the docs list them.
std::span<const SettingSpec> settingSpecs();
/// The setting called `name`, or nullptr.
const SettingSpec* findSetting(std::string_view name);
/// A setting's flag: "--" and the name in kebab case ("maxDepth" →
/// "--max-depth", "mltFeatureSpp" → "--mlt-feature-spp").
std::string settingFlag(const SettingSpec& spec);

/// Named settings as text: integers in decimal, reals in the shortest form that reads back to the
/// same double, "true" / "false", a choice's name.
using SettingValues = std::map<std::string, std::string>;

/// The named settings of command-line assignments "name=value" (glint-render's and glint-final's
/// --set), the value as text (setSetting reads it). Throws glint::Error(InvalidArgument) at
/// `where` ("--set") for an item without "=" or whose name is no setting, listing the names.
SettingValues parseSettingAssignments(const std::vector<std::string>& items,
                                      const std::string& where);
/// --help of a --set that parseSettingAssignments reads: "a render setting name=value
/// (repeatable), scene.json's render keys: " then `keys` (the CLI's examples), ", … " and the page
/// that lists them all.
std::string settingAssignmentsHelp(const std::string& keys);

/// The value of `spec` in `settings`, as text.
std::string settingText(const Settings& settings, const SettingSpec& spec);
/// Sets `spec` in `settings` from `text`, strictly (the whole text, within the range). Throws
/// glint::Error(Format) naming `file` and the place `where`: "expected an integer in [1,
/// 16777216], got \"1e12\"", "unknown sampler 'x' (expected stratified, …)".
void setSetting(Settings& settings, const SettingSpec& spec, std::string_view text,
                const std::string& file = {}, const std::string& where = {});

/// The settings called `names` (every named setting when empty) as text.
SettingValues encodeSettings(const Settings& settings, const std::vector<std::string>& names = {});
/// `settings` with what `values` says of the named settings (a name missing keeps its value;
/// keys that name no setting are left to their owner, as values share a map with other keys).
/// Errors as setSetting's, at `pointer` + name ("/view/" + "spp").
Settings decodeSettings(const SettingValues& values, Settings settings,
                        const std::string& file = {}, const std::string& pointer = {});

/// scene.json's "render" block for `settings`: a JSON object of every named setting (numbers,
/// true/false, strings), as text.
std::string renderBlockJson(const Settings& settings);

/// Records the settings that change the pixels in a frame's metadata: spp, seed and integrator
/// in their FrameMetadata fields (spp: what the render asked; the renderer then records what it
/// completed), the rest as glint:<name> attributes (`strategy` only with mis "none", the
/// Metropolis settings only with the mlt integrator).
void recordSettings(const Settings& settings, FrameMetadata& metadata);
/// `settings` with what a frame's metadata records (recordSettings): spp when > 0, seed,
/// integrator when Glint's, then each glint:<name> attribute, read as setSetting reads (errors
/// name `file` and the attribute, "glint:maxDepth").
Settings recordedSettings(const FrameMetadata& metadata, Settings settings = {},
                          const std::string& file = {});

}  // namespace glint::render
