// The auto pipeline's spill (docs/auto-memory.md): the members' results, written strip by
// strip to one unlinked temporary file as raw floats and read back by rows, so that a later pass
// reads a member's result instead of applying the filter again. The file's pages are the
// kernel's page cache, not the process's resident memory.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "glint/image/image.h"

namespace glint::denoise::detail {

/// Frame-sized images of width × height × channels floats kept by key, each written and read by
/// rows in one temporary file. Thread-safe: different keys (or rows) may be written and read at
/// once. A store that is off (not opened, or after a failed write) holds nothing: has() is false
/// and write() does nothing, so that its user applies the filter again and gets the same floats.
class StripSpill {
  public:
    StripSpill() = default;
    ~StripSpill();
    StripSpill(const StripSpill&) = delete;
    StripSpill& operator=(const StripSpill&) = delete;

    /// The directory of the file: TMPDIR when set and not empty, else /tmp.
    static std::string directory();

    /// Opens the store: a temporary file in `directory`, unlinked at once, for images of
    /// width × height × channels floats. With `checkRoom`, only when the file system has room
    /// for `peakImages` of them with 1 GiB to spare (statvfs). Returns whether the store is on;
    /// when not, warning() says why.
    bool open(const std::string& directory, int width, int height, int channels,
              std::size_t peakImages, bool checkRoom);
    bool on() const;
    /// Whether a write failed (which turned the store off).
    bool failed() const;

    /// Writes `rows` (width × rows.height() × channels) as rows [y0, y0 + rows.height()) of the
    /// image `key`. A failed write turns the store off (warning() says why).
    void write(std::int64_t key, int y0, const Image& rows);
    /// Whether the store is on and holds every row of [y0, y1) of `key`.
    bool has(std::int64_t key, int y0, int y1) const;
    /// Reads rows [y0, y1) of `key` into `out` (resized); false, and `out` untouched, when the
    /// store does not hold them or the read fails.
    bool read(std::int64_t key, int y0, int y1, Image& out) const;
    /// Forgets `key` and gives its space back (its slot is reused by the next new key).
    void drop(std::int64_t key);

    /// Why the store is off, or empty while it is on.
    std::string warning() const;
    /// The bytes written so far.
    std::uint64_t bytesWritten() const;

  private:
    struct Slot {
        std::size_t index = 0;
        std::vector<char> rows;  // 1 where the row was written
    };
    std::uint64_t offsetOf(std::size_t slot, int y) const;
    void fail(const std::string& why);

    int m_fd = -1;
    int m_width = 0, m_height = 0, m_channels = 0;
    std::string m_directory;
    mutable std::mutex m_mutex;
    std::unordered_map<std::int64_t, Slot> m_slots;
    std::vector<std::size_t> m_freeSlots;
    std::size_t m_slotCount = 0;
    bool m_failed = false;
    std::string m_warning;
    std::uint64_t m_bytesWritten = 0;
};

}  // namespace glint::denoise::detail
