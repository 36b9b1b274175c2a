// The description of one user-editable parameter, shared by everything a user edits: a
// denoising filter's parameters (glint::denoise::Filter), a material kind's
// (renderer/src/materials) and a scene's look properties (glint::render::LookProperty).
// Sliders, the bank, the CLI, sessions, scene reading and writing and the docs are generated
// from it.
#pragma once

#include <string>
#include <vector>

namespace glint {

/// How a parameter's range is explored by sliders and the filter bank.
enum class ParamScale { Linear, Log };

/// Description of one parameter: a real number, an integer, a colour (three components), a
/// choice among named options (whose value is the option's index), or a list of strings (a
/// program's argv: see ParamSpec::strings; never sampled by a bank).
struct ParamSpec {
    std::string name;   ///< key used on the command line, in sessions and scenes, e.g. "sigmaS"
    std::string label;  ///< human label, e.g. "spatial sigma (px)"
    double min = 0.0;   ///< range of the value (of each component for a colour)
    double max = 1.0;
    double defaultValue = 0.0;
    ParamScale scale = ParamScale::Linear;
    bool integer = false;
    std::string help;  ///< one sentence
    /// The useful part of [min, max] that sliders and the filter bank explore by default
    /// (Blender's soft limits): [min, max] is what the filter accepts, [softMin, softMax] what
    /// makes sense to try. softMin == softMax keeps the parameter at that value in a bank.
    double softMin = 0.0, softMax = 1.0;
    /// Option names of a choice parameter (value = index, min 0, max size − 1); empty otherwise.
    std::vector<std::string> choices;

    ParamSpec() = default;
    /// A real (integer = false) or integer parameter.
    ParamSpec(std::string name, std::string label, double min, double max, double defaultValue,
              ParamScale scale, bool integer, std::string help)
        : name(std::move(name)),
          label(std::move(label)),
          min(min),
          max(max),
          defaultValue(defaultValue),
          scale(scale),
          integer(integer),
          help(std::move(help)),
          softMin(min),
          softMax(max) {}

    /// This spec with the soft range [lo, hi] (which must lie inside [min, max]).
    ParamSpec soft(double lo, double hi) const;

    /// True for a list-of-strings parameter (ParamSpec::strings).
    bool isStrings = false;
    /// The default of a list-of-strings parameter.
    std::vector<std::string> defaultStrings;
    /// True for a colour: three components (RGB), each in [min, max], all defaulting to
    /// defaultValue (ParamSpec::colour).
    bool isColour = false;

    bool isChoice() const { return !choices.empty(); }

    /// A choice parameter among `options` (at least one), defaulting to option `defaultIndex`.
    static ParamSpec choice(std::string name, std::string label, std::vector<std::string> options,
                            int defaultIndex, std::string help);
    /// A list-of-strings parameter (empty by default): a program and its arguments, for
    /// instance. Its numeric range is [0, 0], so a bank holds it at its value.
    static ParamSpec strings(std::string name, std::string label, std::string help);
    /// A colour parameter: three components, each in [min, max] (grey `defaultValue` by default).
    static ParamSpec colour(std::string name, std::string label, double min, double max,
                            double defaultValue, std::string help);
};

}  // namespace glint
