// ParamSpec's named constructors (glint/image/parameters.h).
#include "glint/image/parameters.h"

#include "glint/image/error.h"

namespace glint {

ParamSpec ParamSpec::choice(std::string name, std::string label, std::vector<std::string> options,
                            int defaultIndex, std::string help) {
    GLINT_CHECK(!options.empty() && defaultIndex >= 0 && defaultIndex < int(options.size()));
    ParamSpec spec;
    spec.name = std::move(name);
    spec.label = std::move(label);
    spec.min = 0.0;
    spec.max = double(options.size() - 1);
    spec.defaultValue = double(defaultIndex);
    spec.scale = ParamScale::Linear;
    spec.integer = true;
    spec.help = std::move(help);
    spec.choices = std::move(options);
    spec.softMin = spec.min;
    spec.softMax = spec.max;
    return spec;
}

ParamSpec ParamSpec::strings(std::string name, std::string label, std::string help) {
    ParamSpec spec(std::move(name), std::move(label), 0.0, 0.0, 0.0, ParamScale::Linear, false,
                   std::move(help));
    spec.isStrings = true;
    return spec;
}

ParamSpec ParamSpec::colour(std::string name, std::string label, double min, double max,
                            double defaultValue, std::string help) {
    ParamSpec spec(std::move(name), std::move(label), min, max, defaultValue, ParamScale::Linear,
                   false, std::move(help));
    spec.isColour = true;
    return spec;
}

ParamSpec ParamSpec::soft(double lo, double hi) const {
    GLINT_CHECK(lo <= hi && lo >= min && hi <= max, "soft range outside [min, max]");
    ParamSpec spec = *this;
    spec.softMin = lo;
    spec.softMax = hi;
    return spec;
}

}  // namespace glint
