// Internals of the filter bank that its own code, the tests and lab/bench use: the
// Latin-hypercube design of the members (sampling.cpp) and the build's bookkeeping on a
// FilterBank (bank.cpp). Not part of the public API (docs/architecture.md, "Public headers").
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "glint/denoise/bank.h"
#include "glint/denoise/filter.h"

namespace glint::denoise::detail {

/// A Latin-hypercube design: n points in [0, 1)^dims with exactly one point in each stratum
/// [i/n, (i+1)/n) of every dimension (McKay, Beckman & Conover 1979), jittered inside the
/// strata; deterministic for a seed. points[i][d].
std::vector<std::vector<double>> latinHypercube(int n, int dims, std::uint64_t seed);

/// Maps u in [0, 1] onto a parameter's soft range by its scale (log or linear); integers and
/// choices are rounded to the nearest allowed value (each of the n values gets 1/n of [0, 1]).
double mapParam(const ParamSpec& spec, double u);

/// The members of a bank over `filters`: first each filter's defaults, then `size` members from
/// a Latin hypercube with one dimension for the filter (continuous in [1, M], rounded) and one
/// per parameter of the filter with the most parameters (unused dimensions ignored). A filter's
/// parameters in `fixed` (BankOptions::filterParams) hold their values in every member of it.
std::vector<BankMember> sampleBank(const std::vector<const Filter*>& filters, int size,
                                   std::uint64_t seed,
                                   const std::map<std::string, ParamValues>& fixed = {});

/// The fixed parameters `fixed` (BankOptions::filterParams) give `filter` (empty when none).
const ParamValues& fixedParams(const std::map<std::string, ParamValues>& fixed,
                               std::string_view filter);

/// The bank buildBank(frame, options) would build, without its results (results() is empty):
/// its members, region, frame size and input hash, for the streamed selection, which filters
/// the members strip by strip (auto_stream.h). Throws like buildBank for bad options.
FilterBank bankWithoutResults(const FrameBuffers& frame, const BankOptions& options);

/// Sets what only a bank's build knows on the bank it returns.
struct BankAccess {
    /// Members left out because they cannot run here.
    static void setUnavailable(FilterBank& bank, std::vector<UnavailableMember> unavailable) {
        bank.m_unavailable = std::move(unavailable);
    }
    /// Members the build read from the cache.
    static void setCacheHits(FilterBank& bank, std::size_t hits) { bank.m_cacheHits = hits; }
    /// For a build of BankOptions::members: see FilterBank::firstMember and the next two.
    static void setMemberRange(FilterBank& bank, std::size_t first, std::size_t bankMembers,
                               bool indexWritten) {
        bank.m_firstMember = first, bank.m_bankMembers = bankMembers,
        bank.m_indexWritten = indexWritten;
    }
};

}  // namespace glint::denoise::detail
