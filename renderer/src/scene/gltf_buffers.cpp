// A glTF asset's buffer bytes (gltf_buffers.h): file regions read on demand, or tinygltf's.
#include "scene/gltf_buffers.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tiny_gltf.h>

#include <cerrno>
#include <string>

#include "glint/image/error.h"

namespace glint::render::detail {

std::unique_ptr<BufferFile> BufferFile::open(const std::filesystem::path& path,
                                             std::uint64_t fileSize, std::uint64_t offset,
                                             std::uint64_t size) {
    if (size == 0 || offset > fileSize || size > fileSize - offset) return nullptr;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return nullptr;
    // The size is checked on the file that is read, not on the name: a file replaced or
    // resized since it was measured is left to tinygltf, which reports it.
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || std::uint64_t(st.st_size) != fileSize) {
        ::close(fd);
        return nullptr;
    }
    std::unique_ptr<BufferFile> out(new BufferFile);
    out->m_fd = fd;
    out->m_path = path;
    out->m_offset = offset;
    out->m_size = std::size_t(size);
    return out;
}

BufferFile::~BufferFile() {
    ::close(m_fd);
}

bool BufferFile::read(std::size_t from, std::size_t count, unsigned char* out) const {
    if (from > m_size || count > m_size - from) return false;
    while (count > 0) {
        const ssize_t n = ::pread(m_fd, out, count, off_t(m_offset + from));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;  // an error, or the file ends early: it was cut short
        out += n, from += std::size_t(n), count -= std::size_t(n);
    }
    return true;
}

void GltfBuffers::setFile(std::size_t index, std::unique_ptr<BufferFile> file) {
    if (m_buffers.size() <= index) m_buffers.resize(index + 1);
    m_buffers[index].data = nullptr;
    m_buffers[index].size = file->size();
    m_buffers[index].file = std::move(file);
}

bool GltfBuffers::fromFile(std::size_t index) const {
    return index < m_buffers.size() && m_buffers[index].file != nullptr;
}

std::vector<std::filesystem::path> GltfBuffers::files() const {
    std::vector<std::filesystem::path> out;
    for (const Buffer& b : m_buffers)
        if (b.file && b.file->path() != m_asset) out.push_back(b.file->path());
    return out;
}

void GltfBuffers::bind(const tinygltf::Model& model) {
    m_buffers.resize(model.buffers.size());
    for (std::size_t i = 0; i < m_buffers.size(); ++i)
        if (!m_buffers[i].file) {
            m_buffers[i].data = model.buffers[i].data.data();
            m_buffers[i].size = model.buffers[i].data.size();
        }
}

const unsigned char* GltfBuffers::bytes(std::size_t index, std::size_t from, std::size_t to,
                                        std::vector<unsigned char>& scratch) const {
    const Buffer& b = m_buffers[index];
    if (!b.file) return b.data + from;
    scratch.resize(to - from);
    if (!b.file->read(from, to - from, scratch.data()))
        throw Error(ErrorKind::Io,
                    "buffer file '" + b.file->path().string() +
                        "' changed while it was read: bytes " + std::to_string(from) + " to " +
                        std::to_string(to) + " of the buffer are no longer in it",
                    m_asset.string(), "buffers[" + std::to_string(index) + "]");
    return scratch.data();
}

}  // namespace glint::render::detail
