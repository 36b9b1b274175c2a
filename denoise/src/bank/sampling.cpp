// The bank's design: a Latin hypercube over the choice of filter and its parameters
// (McKay, Beckman & Conover 1979), mapped onto each parameter's soft range by its scale.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "bank/bank_detail.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/random.h"

namespace glint::denoise::detail {

std::vector<std::vector<double>> latinHypercube(int n, int dims, std::uint64_t seed) {
    if (n < 1 || dims < 0)
        throw Error(ErrorKind::InvalidArgument, "latin hypercube needs n >= 1 and dims >= 0");
    std::vector<std::vector<double>> points(static_cast<std::size_t>(n),
                                            std::vector<double>(static_cast<std::size_t>(dims)));
    SplitMix64 rng(hash64(seed, 0x4c48535f64657369ULL));  // "LHS_desi"
    std::vector<int> strata(static_cast<std::size_t>(n));
    for (int d = 0; d < dims; ++d) {
        // One random permutation of the strata per dimension (Fisher–Yates), then a jitter
        // inside each stratum.
        std::iota(strata.begin(), strata.end(), 0);
        for (int i = n - 1; i > 0; --i)
            std::swap(strata[std::size_t(i)], strata[std::size_t(rng.below(std::uint64_t(i) + 1))]);
        for (int i = 0; i < n; ++i) {
            const double u = (double(strata[std::size_t(i)]) + rng.uniformDouble()) / double(n);
            points[std::size_t(i)][std::size_t(d)] = std::min(u, std::nextafter(1.0, 0.0));
        }
    }
    return points;
}

double mapParam(const ParamSpec& spec, double u) {
    u = std::clamp(u, 0.0, 1.0);
    const double lo = spec.softMin, hi = spec.softMax;
    double value;
    if (spec.integer) {
        // Each of the n allowed values takes 1/n of [0, 1] (on the log scale for log parameters).
        if (spec.scale == ParamScale::Log && lo - 0.5 > 0.0) {
            const double a = std::log(lo - 0.5), b = std::log(hi + 0.5);
            value = std::clamp(std::round(std::exp(a + u * (b - a))), lo, hi);
        } else {
            const double n = hi - lo + 1.0;
            value = lo + std::min(std::floor(u * n), n - 1.0);
        }
    } else if (spec.scale == ParamScale::Log && lo > 0.0) {
        value = std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo)));
    } else {
        value = lo + u * (hi - lo);
    }
    return std::clamp(value, spec.min, spec.max);
}

const ParamValues& fixedParams(const std::map<std::string, ParamValues>& fixed,
                               std::string_view filter) {
    static const ParamValues none;
    const auto it = fixed.find(std::string(filter));
    return it == fixed.end() ? none : it->second;
}

std::vector<BankMember> sampleBank(const std::vector<const Filter*>& filters, int size,
                                   std::uint64_t seed,
                                   const std::map<std::string, ParamValues>& fixed) {
    if (filters.empty())
        throw Error(ErrorKind::InvalidArgument, "a bank needs at least one filter");
    if (size < 1 || size > kMaxBankSize)
        throw Error(ErrorKind::InvalidArgument, "bank size " + std::to_string(size) +
                                                    " must be in [1, " +
                                                    std::to_string(kMaxBankSize) + "]");
    std::vector<BankMember> members;
    // The defaults of every filter are always members, so the bank never loses to them.
    for (const Filter* f : filters)
        members.push_back(
            {std::string(f->name()), resolveParams(*f, fixedParams(fixed, f->name())), true});
    // A filter whose parameters are all fixed (unet; external with its command given) is its
    // default member only and takes no stratum of the design: adding it leaves the other members
    // as they were.
    std::vector<const Filter*> explored;
    for (const Filter* f : filters) {
        const ParamValues& given = fixedParams(fixed, f->name());
        auto isFixed = [&](const ParamSpec& s) {
            return s.softMin == s.softMax || given.count(s.name) || given.strings.count(s.name);
        };
        if (!std::all_of(f->params().begin(), f->params().end(), isFixed)) explored.push_back(f);
    }
    if (explored.empty()) return members;
    std::size_t maxParams = 0;
    for (const Filter* f : explored) maxParams = std::max(maxParams, f->params().size());
    const auto design = latinHypercube(size, 1 + int(maxParams), seed);
    const int m = int(explored.size());
    for (const std::vector<double>& u : design) {
        // Dimension 0 chooses the filter: continuous over [0.5, M + 0.5), rounded to 1 … M, so
        // every filter gets the same share of the strata.
        const int pick = std::clamp(int(std::lround(0.5 + u[0] * double(m))), 1, m) - 1;
        const Filter& f = *explored[std::size_t(pick)];
        const ParamValues& given = fixedParams(fixed, f.name());
        ParamValues params;
        for (std::size_t i = 0; i < f.params().size(); ++i)
            params[f.params()[i].name] = mapParam(f.params()[i], u[1 + i]);
        for (const auto& [name, value] : given) params[name] = value;
        params.strings = given.strings;
        members.push_back({std::string(f.name()), resolveParams(f, params), false});
    }
    return members;
}

}  // namespace glint::denoise::detail
