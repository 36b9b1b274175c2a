// The bytes of a glTF asset's buffers as Glint reads them. A .glb's BIN chunk and buffer files
// stay in their files and are read piece by piece as the accessor readers need them (a megabyte
// at a time, into the reader's own scratch array), so that a large asset's buffers and the mesh
// made from them are never in memory at once. Buffers in data URIs (and any that tinygltf read
// itself) are tinygltf's bytes, read in place.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <vector>

namespace tinygltf {
class Model;
}

namespace glint::render::detail {

/// A region of a file read on demand (pread on a descriptor held open): a file changed while it
/// is read gives a short read, which is an error, never a crash.
class BufferFile {
  public:
    /// Opens bytes [offset, offset + size) of `path` when it is a regular file of exactly
    /// `fileSize` bytes; nothing when it cannot be opened or is of another size (the caller
    /// then leaves it to tinygltf, which reads it as before and reports what is wrong).
    static std::unique_ptr<BufferFile> open(const std::filesystem::path& path,
                                            std::uint64_t fileSize, std::uint64_t offset,
                                            std::uint64_t size);
    ~BufferFile();
    BufferFile(const BufferFile&) = delete;
    BufferFile& operator=(const BufferFile&) = delete;

    const std::filesystem::path& path() const { return m_path; }
    std::size_t size() const { return m_size; }
    /// Reads bytes [from, from + count) of the region into `out`; false when the file no longer
    /// holds them all.
    bool read(std::size_t from, std::size_t count, unsigned char* out) const;

  private:
    BufferFile() = default;
    int m_fd = -1;
    std::filesystem::path m_path;
    std::uint64_t m_offset = 0;
    std::size_t m_size = 0;
};

/// The bytes of every buffer of one asset: in a file, or tinygltf's.
class GltfBuffers {
  public:
    GltfBuffers() = default;
    /// The buffers of the asset `asset` (named in errors).
    explicit GltfBuffers(std::filesystem::path asset) : m_asset(std::move(asset)) {}

    /// Buffer `index` is `file`'s region (its byteLength bytes).
    void setFile(std::size_t index, std::unique_ptr<BufferFile> file);
    /// Whether buffer `index` is read from its file.
    bool fromFile(std::size_t index) const;
    /// The files of the buffers read from a file other than the asset (a .gltf's .bin files).
    std::vector<std::filesystem::path> files() const;
    /// Takes every buffer not read from a file from `model` (its tinygltf-read bytes); call once
    /// the model is read, and keep the model while these bytes are read.
    void bind(const tinygltf::Model& model);

    /// The number of buffers (the model's, once bound).
    std::size_t count() const { return m_buffers.size(); }
    /// Buffer `index`'s size in bytes: its byteLength.
    std::size_t size(std::size_t index) const { return m_buffers[index].size; }
    /// Bytes [from, to) of buffer `index` (to <= size): tinygltf's bytes in place, or the
    /// file's read into `scratch`. Throws glint::Error(Io) naming the asset and `buffers[i]`
    /// when the file no longer holds them (changed since it was opened).
    const unsigned char* bytes(std::size_t index, std::size_t from, std::size_t to,
                               std::vector<unsigned char>& scratch) const;

  private:
    struct Buffer {
        const unsigned char* data = nullptr;  ///< tinygltf's bytes, or null for a file
        std::size_t size = 0;
        std::unique_ptr<BufferFile> file;
    };
    std::filesystem::path m_asset;
    std::vector<Buffer> m_buffers;
};

}  // namespace glint::render::detail
