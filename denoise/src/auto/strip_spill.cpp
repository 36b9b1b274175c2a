// The auto pipeline's spill file (strip_spill.h): one unlinked temporary file holding slots
// of one frame-sized image each, written and read by rows with pwrite and pread.
#include "strip_spill.h"

#include <fcntl.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "glint/image/error.h"

namespace glint::denoise::detail {

namespace {

constexpr std::uint64_t kMiB = 1024 * 1024;
// What the spill leaves free on its file system, at least.
constexpr std::uint64_t kSpare = 1024 * kMiB;

// Writes `bytes` bytes at `offset`, through short writes; the errno text when it fails.
bool writeAll(int fd, const char* data, std::size_t bytes, std::uint64_t offset, std::string& why) {
    while (bytes > 0) {
        const ssize_t n = ::pwrite(fd, data, bytes, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            why = n < 0 ? std::strerror(errno) : "nothing written";
            return false;
        }
        data += n, bytes -= std::size_t(n), offset += std::uint64_t(n);
    }
    return true;
}

// Reads `bytes` bytes at `offset`, through short reads; false at an error or the file's end.
bool readAll(int fd, char* data, std::size_t bytes, std::uint64_t offset) {
    while (bytes > 0) {
        const ssize_t n = ::pread(fd, data, bytes, off_t(offset));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n, bytes -= std::size_t(n), offset += std::uint64_t(n);
    }
    return true;
}

}  // namespace

StripSpill::~StripSpill() {
    if (m_fd >= 0) ::close(m_fd);
}

std::string StripSpill::directory() {
    const char* dir = std::getenv("TMPDIR");
    return dir && *dir ? dir : "/tmp";
}

bool StripSpill::open(const std::string& directory, int width, int height, int channels,
                      std::size_t peakImages, bool checkRoom) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    GLINT_CHECK(m_fd < 0 && width > 0 && height > 0 && channels > 0);
    m_width = width, m_height = height, m_channels = channels, m_directory = directory;
    // Room for the largest number of images held at once, with some to spare.
    if (checkRoom) {
        struct statvfs fs {};
        if (::statvfs(directory.c_str(), &fs) != 0) {
            m_warning =
                "cannot read the free space of " + directory + " (" + std::strerror(errno) + ")";
            return false;
        }
        const std::uint64_t free = std::uint64_t(fs.f_bavail) * std::uint64_t(fs.f_frsize);
        const std::uint64_t needed = std::uint64_t(peakImages) * std::uint64_t(height) *
                                     std::uint64_t(width) * std::uint64_t(channels) * sizeof(float);
        if (needed + kSpare > free) {
            m_warning = directory + " has " + std::to_string(free / kMiB) +
                        " MiB free; the spill needs " + std::to_string(needed / kMiB) +
                        " MiB and leaves " + std::to_string(kSpare / kMiB);
            return false;
        }
    }
    // Create the file and unlink it at once: nothing is left behind on any path.
    std::string name = directory + "/glint-spill-XXXXXX";
    const int fd = ::mkstemp(name.data());
    if (fd < 0) {
        m_warning = "cannot create a file in " + directory + " (" + std::strerror(errno) + ")";
        return false;
    }
    ::unlink(name.c_str());
    m_fd = fd;
    return true;
}

bool StripSpill::on() const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    return m_fd >= 0 && !m_failed;
}

bool StripSpill::failed() const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    return m_failed;
}

std::uint64_t StripSpill::offsetOf(std::size_t slot, int y) const {
    const std::uint64_t rowBytes =
        std::uint64_t(m_width) * std::uint64_t(m_channels) * sizeof(float);
    return (std::uint64_t(slot) * std::uint64_t(m_height) + std::uint64_t(y)) * rowBytes;
}

void StripSpill::fail(const std::string& why) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    if (m_failed) return;
    m_failed = true;
    m_warning = "cannot write the spill file in " + m_directory + " (" + why + ")";
    m_slots.clear();
    // Give the space back; a read already under way fails and its filter is applied again.
    const int truncated = ::ftruncate(m_fd, 0);
    (void)truncated;
}

void StripSpill::write(std::int64_t key, int y0, const Image& rows) {
    std::size_t index = 0;
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        if (m_fd < 0 || m_failed) return;
        GLINT_CHECK(rows.width() == m_width && rows.channels() == m_channels && y0 >= 0 &&
                    y0 + rows.height() <= m_height);
        auto it = m_slots.find(key);
        if (it == m_slots.end()) {
            Slot slot;
            if (m_freeSlots.empty()) {
                slot.index = m_slotCount++;
            } else {
                slot.index = m_freeSlots.back();
                m_freeSlots.pop_back();
            }
            slot.rows.assign(std::size_t(m_height), 0);
            it = m_slots.emplace(key, std::move(slot)).first;
        }
        index = it->second.index;
    }
    const std::size_t bytes = rows.data().size() * sizeof(float);
    std::string why;
    if (!writeAll(m_fd, reinterpret_cast<const char*>(rows.data().data()), bytes,
                  offsetOf(index, y0), why)) {
        fail(why);
        return;
    }
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_bytesWritten += bytes;
    const auto it = m_slots.find(key);
    if (it == m_slots.end()) return;  // dropped or failed meanwhile
    std::fill_n(it->second.rows.begin() + y0, rows.height(), char(1));
}

bool StripSpill::has(std::int64_t key, int y0, int y1) const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    if (m_fd < 0 || m_failed) return false;
    const auto it = m_slots.find(key);
    if (it == m_slots.end() || y0 < 0 || y1 > m_height || y0 >= y1) return false;
    return std::all_of(it->second.rows.begin() + y0, it->second.rows.begin() + y1,
                       [](char written) { return written != 0; });
}

bool StripSpill::read(std::int64_t key, int y0, int y1, Image& out) const {
    if (!has(key, y0, y1)) return false;
    std::size_t index = 0;
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        const auto it = m_slots.find(key);
        if (it == m_slots.end()) return false;
        index = it->second.index;
    }
    Image rows(m_width, y1 - y0, m_channels);
    if (!readAll(m_fd, reinterpret_cast<char*>(rows.data().data()),
                 rows.data().size() * sizeof(float), offsetOf(index, y0)))
        return false;
    out = std::move(rows);
    return true;
}

void StripSpill::drop(std::int64_t key) {
    const std::lock_guard<std::mutex> lock(m_mutex);
    const auto it = m_slots.find(key);
    if (it == m_slots.end()) return;
    const std::size_t index = it->second.index;
    m_slots.erase(it);
    m_freeSlots.push_back(index);
#ifdef FALLOC_FL_PUNCH_HOLE
    // Free its blocks (and page cache) now; without, the slot's next key overwrites them.
    const off_t begin = off_t(offsetOf(index, 0)), length = off_t(offsetOf(index + 1, 0)) - begin;
    const int punched =
        ::fallocate(m_fd, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, begin, length);
    (void)punched;
#endif
}

std::string StripSpill::warning() const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    return m_warning;
}

std::uint64_t StripSpill::bytesWritten() const {
    const std::lock_guard<std::mutex> lock(m_mutex);
    return m_bytesWritten;
}

}  // namespace glint::denoise::detail
