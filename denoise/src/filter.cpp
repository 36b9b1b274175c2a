// Parameter resolution and the checked entry point shared by every filter.
#include "glint/denoise/filter.h"

#include <cmath>
#include <sstream>

#include "glint/image/error.h"

namespace glint::denoise {

namespace {

// "name [min, max] (integer)" for every parameter, for error messages.
std::string describeParams(const Filter& filter) {
    std::ostringstream out;
    bool first = true;
    for (const ParamSpec& spec : filter.params()) {
        out << (first ? "" : ", ") << spec.name << " [" << spec.min << ", " << spec.max << "]"
            << (spec.integer ? " (integer)" : "");
        first = false;
    }
    if (first) out << "(none)";
    return out.str();
}

std::string layerLabel(Layer layer) {
    const std::string_view name = layerInfo(layer).name;
    return name.empty() ? std::string("colour (R,G,B)") : std::string(name);
}

}  // namespace

ParamValues resolveParams(const Filter& filter, const ParamValues& given) {
    const std::string where = "filter '" + std::string(filter.name()) + "'";
    // Reject names the filter does not know.
    for (const auto& [name, value] : given) {
        bool known = false;
        for (const ParamSpec& spec : filter.params()) known = known || spec.name == name;
        if (!known)
            throw Error(
                ErrorKind::InvalidArgument,
                "unknown parameter '" + name + "'; valid parameters: " + describeParams(filter), {},
                where);
    }
    // Fill in defaults and check the values given.
    ParamValues resolved;
    for (const ParamSpec& spec : filter.params()) {
        auto it = given.find(spec.name);
        const double value = it == given.end() ? spec.defaultValue : it->second;
        std::ostringstream range;
        range << "[" << spec.min << ", " << spec.max << "]";
        if (std::isnan(value) || value < spec.min || value > spec.max)
            throw Error(ErrorKind::InvalidArgument,
                        "parameter '" + spec.name + "' = " + std::to_string(value) +
                            " is outside its range " + range.str() +
                            "; valid parameters: " + describeParams(filter),
                        {}, where);
        if (spec.integer && value != std::floor(value))
            throw Error(ErrorKind::InvalidArgument,
                        "parameter '" + spec.name + "' = " + std::to_string(value) +
                            " must be an integer in " + range.str(),
                        {}, where);
        resolved[spec.name] = value;
    }
    return resolved;
}

Image applyFilter(const Filter& filter, const FrameBuffers& frame, const ParamValues& params,
                  const Rect* roi) {
    const std::string where = "filter '" + std::string(filter.name()) + "'";
    if (!frame.has(Layer::Color) || frame.width() <= 0 || frame.height() <= 0)
        throw Error(ErrorKind::InvalidArgument, "the frame has no colour layer or is empty", {},
                    where);
    // Check the feature layers the filter needs, naming every missing one.
    std::string missing;
    for (Layer layer : filter.requiredLayers())
        if (!frame.has(layer)) missing += (missing.empty() ? "" : ", ") + layerLabel(layer);
    if (!missing.empty()) {
        std::string present;
        for (int l = 0; l < kLayerCount; ++l)
            if (frame.has(Layer(l)))
                present += (present.empty() ? "" : ", ") + layerLabel(Layer(l));
        std::string needed;
        for (Layer layer : filter.requiredLayers())
            needed += (needed.empty() ? "" : ", ") + layerLabel(layer);
        throw Error(ErrorKind::InvalidArgument,
                    "missing feature layer(s) " + missing + "; the filter needs " + needed +
                        "; the frame has " + present,
                    {}, where);
    }
    const Rect bounds{0, frame.width(), 0, frame.height()};
    const Rect region = roi ? *roi : bounds;
    if (region.empty() || intersect(region, bounds) != region)
        throw Error(ErrorKind::InvalidArgument,
                    "region of interest x [" + std::to_string(region.x0) + ", " +
                        std::to_string(region.x1) + "), y [" + std::to_string(region.y0) + ", " +
                        std::to_string(region.y1) + ") is empty or outside the " +
                        std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                        " frame",
                    {}, where);
    return filter.apply(frame, resolveParams(filter, params), region);
}

}  // namespace glint::denoise
