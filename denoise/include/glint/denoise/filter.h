// The filter interface: every denoising filter describes its parameters and applies to the colour
// of a FrameBuffers inside a region of interest. The bank, navigation, painting and the CLI treat
// filters as black boxes through this interface.
#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

/// How a parameter's range is explored by sliders and the filter bank.
enum class ParamScale { Linear, Log };

/// Description of one filter parameter.
struct ParamSpec {
    std::string name;   ///< key used on the command line and in sessions, e.g. "sigmaS"
    std::string label;  ///< human label, e.g. "spatial sigma (px)"
    double min = 0.0;
    double max = 1.0;
    double defaultValue = 0.0;
    ParamScale scale = ParamScale::Linear;
    bool integer = false;
    std::string help;  ///< one sentence
};

/// Parameter values by name. Missing names take their defaults (see resolveParams).
using ParamValues = std::map<std::string, double>;

/// A denoising filter. Implementations are stateless and thread-safe: apply() may run
/// concurrently on different inputs.
class Filter {
  public:
    virtual ~Filter() = default;

    /// Registry name, e.g. "bilateral-mc".
    virtual std::string_view name() const = 0;
    /// The short block that opens the filter's source file: what it does, its source paper.
    virtual std::string_view description() const = 0;
    /// Parameter descriptions, in display order.
    virtual const std::vector<ParamSpec>& params() const = 0;
    /// Feature layers the filter cannot run without (besides Color).
    virtual std::vector<Layer> requiredLayers() const { return {}; }
    /// How many pixels beyond a region the filter reads for these (resolved) parameters.
    virtual int margin(const ParamValues& params) const = 0;

    /// Filters the colour of `frame` and returns an image of roi's size (3 channels) holding the
    /// result for the pixels in `roi` (roi must lie inside the frame). Pixels outside roi are read
    /// as inputs where the kernel reaches them. `params` must already be resolved.
    virtual Image apply(const FrameBuffers& frame, const ParamValues& params,
                        const Rect& roi) const = 0;
};

/// Fills in defaults and validates: unknown names, values outside [min, max], non-integers for
/// integer parameters and NaN all throw glint::Error(InvalidArgument) listing the valid names
/// and ranges.
ParamValues resolveParams(const Filter& filter, const ParamValues& given);

/// Checks that `frame` has what `filter` needs (throws glint::Error(InvalidArgument) naming the
/// missing layer), resolves the parameters and applies the filter to the whole frame or `roi`.
Image applyFilter(const Filter& filter, const FrameBuffers& frame, const ParamValues& params,
                  const Rect* roi = nullptr);

}  // namespace glint::denoise
