// The filter bank: candidate results of the chosen filters (defaultBankFilters() unless named)
// at Latin-hypercube samples of their parameters (plus each filter's defaults), computed in
// parallel, optionally for a region only, and cached on disk. Filters are black boxes here: only
// Filter/ParamSpec are used, so a newly registered filter joins the bank without other changes
// (docs/navigation.md; opt-in filters such as nfor join when named).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/progress.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {

namespace detail {
struct BankAccess;
}

/// Largest bank the options accept.
inline constexpr int kMaxBankSize = 4096;

/// One member of a bank: a filter with resolved parameters.
struct BankMember {
    std::string filter;      ///< registry name
    ParamValues params;      ///< resolved
    bool isDefault = false;  ///< the filter's default parameters (always a member)
};

/// A member the bank's options name that cannot run in this process (Filter::unavailable: an
/// external program the user has not allowed, say): left out of the bank, not run.
struct UnavailableMember {
    BankMember member;
    std::string reason;  ///< Filter::unavailable's text: what is wrong and how to put it right
};

/// How a bank is built.
struct BankOptions {
    int size = 64;           ///< Latin-hypercube members, 1 … kMaxBankSize (defaults come on top)
    std::uint64_t seed = 1;  ///< of the Latin hypercube
    std::vector<std::string> filters;  ///< these registry names (empty: defaultBankFilters())
    /// Fixed parameters by filter name (e.g. "external" -> its command): every member of that
    /// filter holds these values and only its other parameters are sampled, so a filter whose
    /// parameters are all fixed is one member. Each name must be one of the bank's filters.
    std::map<std::string, ParamValues> filterParams;
    bool prefilter = false;       ///< build on prefiltered features (motion blur, DOF)
    ParamValues prefilterParams;  ///< prefilter parameters (prefilterParams() specs)
    /// Compute the members over this region only (each filter reads its margin around it);
    /// the whole frame when empty. It must lie inside the frame.
    std::optional<Rect> region;
    /// Cache folder (one EXR per member and index.json); empty: no cache.
    std::filesystem::path cacheDir;
    /// Members done / total, serialised; returning false stops the build between members (and
    /// inside the running ones): buildBank then throws Error(Cancelled).
    ProgressFn progress;
    /// Bytes the build may allocate (estimateMemory); a bank needing more is refused with
    /// Error(OutOfMemory) before any member is computed. 0: what the machine has available.
    std::uint64_t memoryLimit = 0;
    /// Compute only members [first, second) of the bank's member list (clamped to its length;
    /// an empty range computes nothing), for a bank split over machines sharing cacheDir
    /// (docs/distributed.md). Each such build records its members in a partial index; the one
    /// that finds every member present writes index.json, the same as one machine's build.
    std::optional<std::pair<int, int>> members;
};

/// Throws glint::Error(InvalidArgument) naming the first bad option (size, unknown filter, a
/// fixed parameter the filter does not have or outside its range...).
void validate(const BankOptions& options);

/// A computed bank: its members and their results over its region.
class FilterBank {
  public:
    FilterBank() = default;
    FilterBank(std::vector<BankMember> members, std::vector<Image> results, Rect region,
               int frameWidth, int frameHeight, std::uint64_t inputHash);

    const std::vector<BankMember>& members() const { return m_members; }
    std::size_t size() const { return m_members.size(); }
    /// Result of member i over region() (3 channels, region-sized).
    const Image& result(std::size_t i) const { return m_results[i]; }
    const std::vector<Image>& results() const { return m_results; }
    /// Members the options name that cannot run in this process (an external program not
    /// allowed), left out of members(): never run, listed with the reason.
    const std::vector<UnavailableMember>& unavailable() const { return m_unavailable; }
    /// The region the results cover (frame coordinates).
    const Rect& region() const { return m_region; }
    int frameWidth() const { return m_frameWidth; }
    int frameHeight() const { return m_frameHeight; }
    /// hashFrame() of the input the bank was computed from (after prefiltering: of the input).
    std::uint64_t inputHash() const { return m_inputHash; }
    /// Members read from the cache (the rest were computed) by the build that made this bank.
    std::size_t cacheHits() const { return m_cacheHits; }
    /// For a build of BankOptions::members: the index of the first member held here in the whole
    /// bank, the whole bank's member count, and whether this build completed index.json.
    std::size_t firstMember() const { return m_firstMember; }
    std::size_t bankMembers() const { return m_bankMembers ? m_bankMembers : m_members.size(); }
    bool indexWritten() const { return m_indexWritten; }

  private:
    // The build records its cache hits and member range (src/bank/bank_detail.h).
    friend struct detail::BankAccess;

    std::vector<BankMember> m_members;
    std::vector<Image> m_results;
    std::vector<UnavailableMember> m_unavailable;
    Rect m_region;
    int m_frameWidth = 0, m_frameHeight = 0;
    std::uint64_t m_inputHash = 0;
    std::size_t m_cacheHits = 0;
    std::size_t m_firstMember = 0, m_bankMembers = 0;
    bool m_indexWritten = true;
};

/// Bytes buildBank(frame, options) allocates at most besides `frame`: one region-sized RGB float
/// result per member, a prefiltered copy of the frame when asked, and the working images of the
/// members running at once (one per hardware thread).
std::uint64_t estimateMemory(const FrameBuffers& frame, const BankOptions& options);

/// Builds the bank of `frame`: members in parallel (TBB), each result cached when a cache folder
/// is given. A member that cannot run here (Filter::unavailable) is left out and listed in
/// FilterBank::unavailable(); when no member can run, Error(InvalidArgument) gives the reasons. A
/// cache entry is reused only when the input hash, filter name, parameters, filter version,
/// prefilter settings and region all match and its pixels pass their checksum; a damaged entry is
/// recomputed. Throws glint::Error: InvalidArgument for bad options (or a frame lacking a layer
/// every selected filter needs), OutOfMemory when estimateMemory exceeds the limit, Cancelled when
/// progress says stop, Io when the cache cannot be written.
FilterBank buildBank(const FrameBuffers& frame, const BankOptions& options);

/// Opens the bank cached in `dir` for `frame`: the options are read from the folder's index,
/// intact entries are read and damaged or missing ones recomputed. A member the folder names
/// that cannot run here (an external program not allowed) is not run: it is listed in
/// FilterBank::unavailable(). Throws glint::Error(Format)
/// naming the folder when it holds no bank or the bank of another image.
FilterBank openBank(const FrameBuffers& frame, const std::filesystem::path& dir,
                    const ProgressFn& progress = {});

/// The options a cache folder was built with (its index.json). Throws glint::Error(Io/Format)
/// naming the folder or file.
BankOptions readBankOptions(const std::filesystem::path& dir);

/// 64-bit hash of a frame's size and every layer's pixels: the cache key of an input.
std::uint64_t hashFrame(const FrameBuffers& frame);

}  // namespace glint::denoise
