#include "glint/denoise/registry.h"

#include <algorithm>
#include <iterator>
#include <memory>
#include <string>

#include "filters/factories.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace {
// Built once on first use, then immutable. A new filter adds one line here.
std::vector<std::unique_ptr<Filter>> makeAll() {
    std::vector<std::unique_ptr<Filter>> filters;
    filters.push_back(makeGaussianFilter());
    filters.push_back(makeBilateralFilter());
    filters.push_back(makeBilateralMcFilter());
    filters.push_back(makeCrossBilateralFilter());
    filters.push_back(makeGuidedFilter());
    filters.push_back(makeNlMeansFilter());
    filters.push_back(makeNforFilter());
    filters.push_back(makeUNetFilter());
    filters.push_back(makeExternalFilter());
    filters.push_back(makeIdentityFilter());
    return filters;
}

// Filters left out of the default bank: they join a bank only when named (--filters), so that
// the default bank, and the quality tables measured on it, stay as they were.
constexpr std::string_view kOptInFilters[] = {"nfor", "external", "identity"};

bool optIn(const Filter& f) {
    return std::find(std::begin(kOptInFilters), std::end(kOptInFilters), f.name()) !=
           std::end(kOptInFilters);
}
}  // namespace

const std::vector<const Filter*>& allFilters() {
    static const std::vector<std::unique_ptr<Filter>> owned = makeAll();
    static const std::vector<const Filter*> view = [] {
        std::vector<const Filter*> v;
        for (const auto& f : owned) v.push_back(f.get());
        return v;
    }();
    return view;
}

std::vector<const Filter*> defaultBankFilters(std::vector<LeftOutFilter>* leftOut) {
    std::vector<const Filter*> v;
    for (const Filter* f : allFilters()) {
        if (optIn(*f)) continue;
        // A filter that cannot run here with its defaults (unet without its weights) is left out.
        if (std::string why = f->unavailable(resolveParams(*f, {})); !why.empty()) {
            if (leftOut) leftOut->push_back({std::string(f->name()), std::move(why)});
            continue;
        }
        v.push_back(f);
    }
    return v;
}

const Filter& findFilter(std::string_view name) {
    for (const Filter* f : allFilters())
        if (f->name() == name) return *f;
    std::string valid;
    for (const Filter* f : allFilters())
        valid += (valid.empty() ? "" : ", ") + std::string(f->name());
    throw Error(ErrorKind::InvalidArgument,
                "unknown filter '" + std::string(name) + "'; valid filters: " + valid);
}

}  // namespace glint::denoise
