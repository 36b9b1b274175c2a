// The filter interface: every denoising filter describes its parameters and applies to the colour
// of a FrameBuffers inside a region of interest. The bank, navigation, painting and the CLI treat
// filters as black boxes through this interface.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/image/parameters.h"

namespace glint::denoise {

/// Filter parameters are described by the description every user-editable parameter shares
/// (glint/image/parameters.h).
using glint::ParamScale;
using glint::ParamSpec;

/// The largest radiance magnitude every filter and auto are held to (docs/denoise.md, "Numerical
/// range"): within ±kMaxRadiance the output is finite. Beyond it a filter may treat the pixel as
/// missing (nfor) and auto's error estimate refuses the frame.
inline constexpr float kMaxRadiance = 1e30f;

/// Parameter values by name: numbers (real, integer, choice) in the map itself, lists of strings
/// in `strings`. Missing names take their defaults (see resolveParams).
struct ParamValues : std::map<std::string, double> {
    using std::map<std::string, double>::map;
    ParamValues() = default;
    /// Numbers only (a plain map of numeric parameters converts implicitly).
    ParamValues(std::map<std::string, double> numbers)  // NOLINT(google-explicit-constructor)
        : std::map<std::string, double>(std::move(numbers)) {}
    /// Values of list-of-strings parameters (ParamSpec::strings), by name.
    std::map<std::string, std::vector<std::string>> strings;

    friend bool operator==(const ParamValues&, const ParamValues&) = default;
};

/// The spec called `name` in `specs`, or nullptr.
const ParamSpec* findParam(const std::vector<ParamSpec>& specs, std::string_view name);

/// Parses a value as a user types it: a number, or one of a choice parameter's option names (a
/// choice also accepts its index). Throws glint::Error(InvalidArgument) naming the options.
double parseParamValue(const ParamSpec& spec, const std::string& text);

/// The text of a value: the option name of a choice, else the number ("%g").
std::string formatParamValue(const ParamSpec& spec, double value);

/// Sets parameter `spec` in `values` from the text a user types: parseParamValue for a number
/// or choice; for a list of strings, a JSON array of strings (["/opt/bin/tool", "{color}"]) or
/// else the text as a one-element list. Throws glint::Error(InvalidArgument).
void setParamFromText(const ParamSpec& spec, const std::string& text, ParamValues& values);

/// The text of parameter `spec` in resolved `values`: formatParamValue, or for a list of
/// strings the JSON array (what setParamFromText reads back).
std::string formatParam(const ParamSpec& spec, const ParamValues& values);

/// The short text of parameter `spec` in `values` for a label or a line of output: for a number
/// or a choice formatParamValue; for a list of strings its items in brackets, each quoted as a
/// POSIX shell would need it ('my file'), shortened past `maxChars` bytes by writing the
/// arguments' paths by their file names ("…/script.py") and then by cutting the tail (" …]";
/// the program's path by its file name only when it alone does not fit). Not read back:
/// formatParam is the exact form.
std::string paramSummary(const ParamSpec& spec, const ParamValues& values,
                         std::size_t maxChars = 72);

/// "name=value name=value ..." (paramSummary) for every parameter of `specs` that `values`
/// holds, in the specs' order: a bank member's or a layer's one-line description.
std::string paramsSummary(const std::vector<ParamSpec>& specs, const ParamValues& values);

/// Fills in defaults and validates against `specs`: unknown names, values outside [min, max],
/// non-integers for integer or choice parameters, NaN, a number for a list of strings or a list
/// for a number all throw glint::Error(InvalidArgument) listing the valid names and ranges;
/// `where` names the owner ("filter 'gaussian'").
ParamValues resolveParams(const std::vector<ParamSpec>& specs, const ParamValues& given,
                          const std::string& where);

/// What kind of operator a filter is, for the code and the tests that reason about its output
/// (tests ask a filter for its kind, never for its name). The defaults describe Glint's
/// classical filters.
struct FilterTraits {
    /// How the output relates to the input's values.
    enum class Output {
        /// A normalised weighted average of input pixels (non-negative weights summing to one): a
        /// constant image stays constant, to float rounding.
        Average,
        /// A prediction (a trained network): a constant image comes out only close to constant
        /// (the network's output is not a convex combination of its inputs).
        Prediction,
    };
    /// How a missing (NaN or infinite) colour value is read.
    enum class Missing {
        /// Glint's policy (docs/denoise.md): no weight as a neighbour, the pixel's own output
        /// from its finite neighbours; nothing farther than margin() from it changes.
        Neighbours,
        /// As Open Image Denoise reads it: NaN and -Inf as 0, +Inf as the largest float. A
        /// statistic of the whole frame (an autoexposure) sees that value, so every pixel may
        /// move; the output is that of the frame with 0 in place of a NaN.
        ReadAsZero,
    };
    Output output = Output::Average;
    Missing missing = Missing::Neighbours;
    /// Whether the output is smoother than the input (every filter but the identity, whose
    /// finite pixels come out as they went in: auto's candidate where no filter helps).
    bool smooths = true;
};

/// A denoising filter. Implementations are stateless and thread-safe: apply() may run
/// concurrently on different inputs.
class Filter {
  public:
    virtual ~Filter() = default;

    /// Registry name, e.g. "bilateral-mc".
    virtual std::string_view name() const = 0;
    /// Changes whenever the filter's output for the same input and parameters changes, so that
    /// cached results of an older version are never reused.
    virtual std::string_view version() const { return "1"; }
    /// The short block that opens the filter's source file: what it does, its source paper.
    virtual std::string_view description() const = 0;
    /// Parameter descriptions, in display order.
    virtual const std::vector<ParamSpec>& params() const = 0;
    /// Feature layers the filter cannot run without (besides Color) for these resolved
    /// parameters (a guide layer chosen by a parameter, for instance).
    virtual std::vector<Layer> requiredLayers(const ParamValues& /*params*/) const { return {}; }
    /// Why the filter cannot run here with these resolved parameters (empty when it can): a
    /// program the user has not allowed, for instance. applyFilter refuses such parameters;
    /// a session or bank that names them opens with the layer or member marked unavailable.
    virtual std::string unavailable(const ParamValues& /*params*/) const { return {}; }
    /// What kind of operator the filter is (FilterTraits: Glint's classical kernels by default).
    virtual FilterTraits traits() const { return {}; }
    /// How many pixels beyond a region the filter reads for these (resolved) parameters.
    virtual int margin(const ParamValues& params) const = 0;

    /// Filters the colour of `frame` and returns an image of roi's size (3 channels) holding the
    /// result for the pixels in `roi` (roi must lie inside the frame). Pixels outside roi are read
    /// as inputs where the kernel reaches them. `params` must already be resolved. Parallel loops
    /// run through `work`, which reports progress and throws Error(Cancelled) when stopped.
    virtual Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                        WorkContext& work) const = 0;

    /// The divergence of apply() when the filter can give it cheaply: per pixel of `roi` and
    /// channel c, ∂out(p, c)/∂in(p, c) for a frame without missing pixels (roi-sized, 3
    /// channels). The default returns nothing: SURE then estimates it by Monte Carlo (sure.h).
    virtual std::optional<Image> divergence(const FrameBuffers& /*frame*/,
                                            const ParamValues& /*params*/,
                                            const Rect& /*roi*/) const {
        return std::nullopt;
    }
};

/// Resolves the parameters of `filter` (resolveParams over its specs).
ParamValues resolveParams(const Filter& filter, const ParamValues& given);

/// Options of applyFilter.
struct FilterOptions {
    /// Filter only this region (it must lie inside the frame); the whole frame when empty.
    std::optional<Rect> region;
    /// Called with the fraction done (serialised, from worker threads); returning false stops
    /// the filter within one row per thread, and applyFilter then throws Error(Cancelled).
    ProgressFn progress;
    /// Worker threads: 0 runs in the caller's thread pool (all cores, or the share of an
    /// enclosing parallel job such as a filter bank); n > 0 runs on a private pool of n threads.
    int threads = 0;
};

/// Checks that `frame` has what `filter` needs for these parameters (throws
/// glint::Error(InvalidArgument) naming the missing layer, or the reason when
/// Filter::unavailable says it cannot run), resolves the parameters and applies
/// the filter to the whole frame or the region. Returns an image of the region's size.
Image applyFilter(const Filter& filter, const FrameBuffers& frame, const ParamValues& params,
                  const FilterOptions& options = {});

}  // namespace glint::denoise
