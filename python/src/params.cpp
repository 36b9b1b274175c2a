// Parameter descriptions (ParamSpec) and values between Glint and Python dicts: one conversion for
// filter parameters, prefilter parameters and look properties.
#include <pybind11/stl.h>

#include "bindings.h"
#include "glint/denoise/filter.h"
#include "glint/image/error.h"

namespace glint::python {

py::dict specDict(const ParamSpec& spec) {
    py::dict d;
    d["name"] = spec.name;
    d["label"] = spec.label;
    d["help"] = spec.help;
    d["min"] = spec.min;
    d["max"] = spec.max;
    d["default"] = spec.isChoice()
                       ? py::object(py::str(spec.choices[std::size_t(spec.defaultValue)]))
                       : py::object(py::float_(spec.defaultValue));
    d["soft_min"] = spec.softMin;
    d["soft_max"] = spec.softMax;
    d["scale"] = spec.scale == ParamScale::Log ? "log" : "linear";
    d["integer"] = spec.integer;
    d["choices"] = spec.choices;
    d["colour"] = spec.isColour;
    d["strings"] = spec.isStrings;
    return d;
}

std::map<std::string, double> numbersFromDict(
    const std::vector<ParamSpec>& specs, py::handle values, const std::string& where,
    std::map<std::string, std::vector<std::string>>* strings) {
    std::map<std::string, double> numbers;
    if (values.is_none()) return numbers;
    if (!py::isinstance<py::dict>(values))
        throw Error(ErrorKind::InvalidArgument, "expected a dict of parameter values", {}, where);
    for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(values)) {
        const std::string name = py::str(key);
        const ParamSpec* spec = denoise::findParam(specs, name);
        // Unknown names go on as they are: resolveParams names them and lists the valid ones.
        if (py::isinstance<py::str>(value)) {
            if (!spec)
                throw Error(ErrorKind::InvalidArgument, "unknown parameter '" + name + "'", {},
                            where);
            if (spec->isStrings && strings) {
                (*strings)[name] = {value.cast<std::string>()};
                continue;
            }
            numbers[name] = denoise::parseParamValue(*spec, value.cast<std::string>());
        } else if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
            if (!spec || !spec->isStrings || !strings)
                throw Error(ErrorKind::InvalidArgument, "'" + name + "' takes a number, not a list",
                            {}, where);
            (*strings)[name] = value.cast<std::vector<std::string>>();
        } else if (py::isinstance<py::bool_>(value) || py::isinstance<py::int_>(value) ||
                   py::isinstance<py::float_>(value)) {
            numbers[name] = value.cast<double>();
        } else {
            numbers[name] = py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
        }
    }
    return numbers;
}

py::dict valuesDict(const std::vector<ParamSpec>& specs,
                    const std::map<std::string, double>& numbers,
                    const std::map<std::string, std::vector<std::string>>& strings) {
    py::dict d;
    for (const auto& [name, value] : numbers) {
        const ParamSpec* spec = denoise::findParam(specs, name);
        if (spec && spec->isChoice() && value >= 0 && value < double(spec->choices.size()))
            d[py::str(name)] = spec->choices[std::size_t(value)];
        else if (spec && spec->integer)
            d[py::str(name)] = static_cast<long long>(value);
        else
            d[py::str(name)] = value;
    }
    for (const auto& [name, list] : strings) d[py::str(name)] = list;
    return d;
}

std::optional<Rect> regionFrom(py::handle region) {
    if (region.is_none()) return std::nullopt;
    const auto v = region.cast<std::vector<int>>();
    if (v.size() != 4)
        throw Error(ErrorKind::InvalidArgument, "expected (x0, y0, x1, y1)", {}, "region");
    return Rect{v[0], v[2], v[1], v[3]};
}

py::tuple regionTuple(const Rect& r) {
    return py::make_tuple(r.x0, r.y0, r.x1, r.y1);
}

}  // namespace glint::python
