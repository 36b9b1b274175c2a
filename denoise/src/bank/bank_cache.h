// The bank's disk cache: one EXR per member named by its key, and index.json recording the
// input, the options and every member's key, file and pixel checksum (docs/navigation.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/denoise/bank.h"

namespace glint::denoise::detail {

/// Reads and writes the cache folder of one bank build. With an empty folder it does nothing.
class BankCache {
  public:
    BankCache(std::filesystem::path dir, std::uint64_t inputHash, int width, int height,
              const BankOptions& options);

    /// The key of a member's result: input hash, filter name and version, parameters,
    /// prefilter settings and region.
    std::uint64_t key(const BankMember& member, const Rect& region) const;
    /// Reads the cached result of `key` into `out`; false when absent or damaged (unreadable,
    /// wrong size, wrong key or checksum) — then it must be recomputed.
    bool read(std::uint64_t key, const Rect& region, Image& out) const;
    /// Writes a computed result (thread-safe).
    void write(std::uint64_t key, const BankMember& member, const Rect& region,
               const Image& result);
    /// Writes index.json (atomically) for these members, listing those left out as unavailable,
    /// and removes member files of other inputs or settings.
    void writeIndex(const std::vector<BankMember>& members, const std::vector<std::uint64_t>& keys,
                    const Rect& region, const std::vector<UnavailableMember>& unavailable);

    /// Records members [first, end) (computed or read by this build) in the partial index
    /// index.members-FIRST-END.json (atomically), for a bank built in parts.
    void writePartialIndex(const std::vector<BankMember>& members,
                           const std::vector<std::uint64_t>& keys, std::size_t first,
                           std::size_t end, const Rect& region);
    /// Reads every partial index of this input and options in the folder; when together they
    /// hold every member, writes index.json (writeIndex), removes the partial indices and
    /// returns true.
    bool mergePartialIndices(const std::vector<BankMember>& members,
                             const std::vector<std::uint64_t>& keys, const Rect& region,
                             const std::vector<UnavailableMember>& unavailable);

    /// Removes the stale temporary files of an interrupted build from the folder: Glint's own
    /// temporary names of its members and indices (bankTemporaryOwner) whose process no longer
    /// runs on this machine and which have not changed for kStaleTemporarySeconds (a part
    /// built on another machine sharing the folder may be writing one). Other files stay.
    void removeStaleTemporaries() const;

  private:
    /// The options block of index.json (without the member range).
    nlohmann::json optionsJson() const;

    struct Entry {
        std::string file;
        std::uint64_t checksum = 0;
    };
    std::filesystem::path m_dir;
    std::uint64_t m_inputHash;
    int m_width, m_height;
    BankOptions m_options;
    std::string m_prefilterKey;
    mutable std::mutex m_mutex;
    std::map<std::uint64_t, Entry> m_entries;  // from the existing index, plus new writes
};

/// How a build uses its cache folder.
enum class CacheMode {
    ReadWrite,  ///< buildBank: computed members, the index, stale temporaries are written/removed
    ReadOnly,   ///< openBank: intact entries are read, the rest computed in memory; no writes
};

/// buildBank with the cache folder used as `mode` says.
FilterBank buildBank(const FrameBuffers& frame, const BankOptions& options, CacheMode mode);

/// Seconds a temporary file of a finished process must have been left unchanged before a build
/// removes it.
inline constexpr double kStaleTemporarySeconds = 60.0;

/// The process id in a temporary name writeAtomically gives a file of a bank folder
/// (temporaryPathFor: ".m-KEY.tmp-PID.exr", ".index.tmp-PID.json",
/// ".index.members-A-B.tmp-PID.json"); 0 for any other name.
long bankTemporaryOwner(const std::string& fileName);

/// The cache key of a member's result from everything that determines it.
std::uint64_t memberKey(std::uint64_t inputHash, const std::string& filter,
                        std::string_view version, const ParamValues& params,
                        const std::string& prefilterKey, const Rect& region);

/// Hex text of a 64-bit value (16 digits) and back (throws glint::Error(Format)).
std::string toHex(std::uint64_t value);
std::uint64_t fromHex(const std::string& text);

/// Hash of an image's size and pixels (the cache checksum).
std::uint64_t hashImage(const Image& image);

}  // namespace glint::denoise::detail
