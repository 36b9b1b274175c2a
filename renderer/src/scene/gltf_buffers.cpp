// A glTF asset's buffer bytes (gltf_buffers.h): read-only file mappings and the pages given back
// as the accessor readers consume them.
#include "scene/gltf_buffers.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <tiny_gltf.h>

#include <algorithm>
#include <cstdint>

namespace glint::render::detail {

namespace {

std::size_t systemPageSize() {
    static const std::size_t size = std::size_t(sysconf(_SC_PAGESIZE));
    return size;
}

}  // namespace

std::pair<std::size_t, std::size_t> pagesToRelease(std::size_t dataOffset, std::size_t length,
                                                   std::size_t from, std::size_t to,
                                                   std::size_t pageSize) {
    if (from >= to) return {0, 0};
    // Round outward to whole pages: a page partly read is read again on its next touch, which
    // costs a page fault, never a wrong byte.
    from = from > kMappedBehind ? from - kMappedBehind : 0;
    const std::size_t first = (dataOffset + from) / pageSize * pageSize;
    const std::size_t last =
        std::min(length, (dataOffset + to + pageSize - 1) / pageSize * pageSize);
    return first < last ? std::pair{first, last} : std::pair<std::size_t, std::size_t>{0, 0};
}

std::unique_ptr<MappedFile> MappedFile::map(const std::filesystem::path& path,
                                            std::uint64_t fileSize, std::uint64_t offset,
                                            std::uint64_t size) {
    if (size == 0 || offset > fileSize || size > fileSize - offset) return nullptr;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return nullptr;
    // The size is checked on the file that is mapped, not on the name: a file replaced or
    // resized since it was measured is left to the reading path, which reports it.
    struct stat st {};
    std::unique_ptr<MappedFile> out;
    if (::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && std::uint64_t(st.st_size) == fileSize) {
        const std::size_t page = systemPageSize();
        const std::uint64_t start = offset / page * page;
        const std::size_t length = std::size_t(offset + size - start);
        void* base = ::mmap(nullptr, length, PROT_READ, MAP_PRIVATE, fd, off_t(start));
        if (base != MAP_FAILED) {
            out.reset(new MappedFile);
            out->m_base = base;
            out->m_length = length;
            out->m_data = static_cast<const unsigned char*>(base) + (offset - start);
            out->m_size = std::size_t(size);
        }
    }
    ::close(fd);  // the mapping keeps the file
    return out;
}

MappedFile::~MappedFile() {
    ::munmap(m_base, m_length);
}

void MappedFile::release(std::size_t from, std::size_t to) const {
    const std::size_t dataOffset = std::size_t(m_data - static_cast<const unsigned char*>(m_base));
    const auto [first, last] = pagesToRelease(dataOffset, m_length, from, to, systemPageSize());
    // On a read-only private mapping no page was ever copied, so MADV_DONTNEED drops only what
    // can be read again from the file.
    if (first < last) ::madvise(static_cast<char*>(m_base) + first, last - first, MADV_DONTNEED);
}

void GltfBuffers::setMapped(std::size_t index, std::unique_ptr<MappedFile> file) {
    if (m_buffers.size() <= index) m_buffers.resize(index + 1);
    m_buffers[index].bytes = {file->data(), file->size()};
    m_buffers[index].file = std::move(file);
}

bool GltfBuffers::mapped(std::size_t index) const {
    return index < m_buffers.size() && m_buffers[index].file != nullptr;
}

void GltfBuffers::bind(const tinygltf::Model& model) {
    m_buffers.resize(model.buffers.size());
    for (std::size_t i = 0; i < m_buffers.size(); ++i)
        if (!m_buffers[i].file)
            m_buffers[i].bytes = {model.buffers[i].data.data(), model.buffers[i].data.size()};
}

void GltfBuffers::release(std::size_t index, std::size_t from, std::size_t to) const {
    if (index < m_buffers.size() && m_buffers[index].file)
        m_buffers[index].file->release(from, std::min(to, m_buffers[index].bytes.size));
}

}  // namespace glint::render::detail
