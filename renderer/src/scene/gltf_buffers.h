// The bytes of a glTF asset's buffers as Glint reads them. A .glb's BIN chunk and buffer files
// are mapped read-only from their files rather than read into memory, and the accessor readers
// give the pages they have copied out back (release), so that a large asset's buffers and the
// mesh made from them are never resident at once. Buffers in data URIs (and any that tinygltf
// read itself) are tinygltf's bytes. The mappings end with the object.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

namespace tinygltf {
class Model;
}

namespace glint::render::detail {

/// A file region mapped read-only (mmap, MAP_PRIVATE, PROT_READ): file-backed pages count in the
/// process's resident size only while they are resident, and giving them back is always safe (a
/// page touched again is read again from the file).
class MappedFile {
  public:
    /// Maps bytes [offset, offset + size) of `path` when the file is a regular file of exactly
    /// `fileSize` bytes; nothing when it cannot be opened, is of another size or cannot be
    /// mapped (the caller then reads it as before, with that path's errors).
    static std::unique_ptr<MappedFile> map(const std::filesystem::path& path,
                                           std::uint64_t fileSize, std::uint64_t offset,
                                           std::uint64_t size);
    ~MappedFile();
    MappedFile(const MappedFile&) = delete;
    MappedFile& operator=(const MappedFile&) = delete;

    const unsigned char* data() const { return m_data; }
    std::size_t size() const { return m_size; }
    /// Gives back the pages holding bytes [from, to) of data() (madvise MADV_DONTNEED).
    void release(std::size_t from, std::size_t to) const;

  private:
    MappedFile() = default;
    void* m_base = nullptr;    ///< the mapping (page-aligned)
    std::size_t m_length = 0;  ///< bytes mapped from m_base
    const unsigned char* m_data = nullptr;
    std::size_t m_size = 0;
};

/// How far behind the bytes just read the kernel may have mapped pages again: a page fault
/// maps the whole folio of the page cache that holds the page (up to 2 MB on Linux 6, PMD-mapped
/// or not) or its fault-around window (64 KB), so a fault at the start of a read maps pages
/// before it that were given back.
inline constexpr std::size_t kMappedBehind = std::size_t(2) << 20;

/// The page-aligned range [first, last) of a mapping of `length` bytes to give back once bytes
/// [from, to) of data starting `dataOffset` bytes into the mapping are read: every page that
/// holds them, partly or wholly, and those up to kMappedBehind before, clamped to the mapping;
/// empty when [from, to) is.
std::pair<std::size_t, std::size_t> pagesToRelease(std::size_t dataOffset, std::size_t length,
                                                   std::size_t from, std::size_t to,
                                                   std::size_t pageSize);

/// The bytes of every buffer of one asset: mapped, or tinygltf's.
class GltfBuffers {
  public:
    /// The bytes of one buffer: `size` is its byteLength.
    struct Bytes {
        const unsigned char* data = nullptr;
        std::size_t size = 0;
    };

    /// Buffer `index` is `file`'s mapping (its byteLength bytes).
    void setMapped(std::size_t index, std::unique_ptr<MappedFile> file);
    /// Whether buffer `index` is mapped.
    bool mapped(std::size_t index) const;
    /// Takes every buffer that is not mapped from `model` (its tinygltf-read bytes); call once
    /// the model is read, and keep the model while these bytes are read.
    void bind(const tinygltf::Model& model);

    /// The number of buffers (the model's, once bound).
    std::size_t count() const { return m_buffers.size(); }
    /// Buffer `index`'s bytes (index below count()).
    Bytes bytes(std::size_t index) const { return m_buffers[index].bytes; }
    /// Gives back the resident pages of bytes [from, to) of buffer `index` when it is mapped
    /// (they are read again from the file if touched); nothing for tinygltf's bytes.
    void release(std::size_t index, std::size_t from, std::size_t to) const;

  private:
    struct Buffer {
        Bytes bytes;
        std::unique_ptr<MappedFile> file;
    };
    std::vector<Buffer> m_buffers;
};

}  // namespace glint::render::detail
