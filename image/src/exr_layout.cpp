#include "exr_layout.h"

#include <OpenEXR/ImfBoxAttribute.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <OpenEXR/openexr.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <limits>
#include <mutex>
#include <set>
#include <sstream>

#include "direct_formats.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "image_files.h"

namespace glint::detail {

namespace {

/// "part 1 ('albedo')", or "part 1" for a part without a name.
std::string partName(const Imf::Header& header, int part) {
    return "part " + std::to_string(part) +
           (header.hasName() ? " ('" + header.name() + "')" : std::string());
}

bool sameLetters(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower((unsigned char)x) == std::tolower((unsigned char)y);
           });
}

/// Where a channel's suffix goes within its layer (the order image tools show: colour, then
/// alpha; a position or normal's X, Y, Z in that order); 1000 for the rest.
int suffixRank(std::string_view suffix, bool xyzLayer) {
    static constexpr std::array<std::string_view, 20> kUsual{
        "R",     "Red", "G",  "Green", "B",  "Blue", "Y",  "real", "imag",  "A",
        "Alpha", "AR",  "RA", "AG",    "GA", "AB",   "BA", "Z",    "Depth", "Zback"};
    static constexpr std::array<std::string_view, 21> kXyz{
        "R", "Red",   "G",  "Green", "B",  "Blue", "X",  "Y",  "Z",     "real", "imag",
        "A", "Alpha", "AR", "RA",    "AG", "GA",   "AB", "BA", "Depth", "Zback"};
    const auto rank = [&](const auto& order) {
        for (std::size_t i = 0; i < order.size(); ++i)
            if (sameLetters(suffix, order[i])) return int(i);
        return 1000;
    };
    return xyzLayer ? rank(kXyz) : rank(kUsual);
}

/// The channel names of `channels` in the order image tools show them: by layer (the name up to
/// its last dot), then by suffixRank, then by name.
std::vector<std::string> presentedOrder(const Imf::ChannelList& channels) {
    struct Name {
        std::string full, layer, suffix;
        int rank = 0;
    };
    std::vector<Name> names;
    for (auto c = channels.begin(); c != channels.end(); ++c) {
        Name n{c.name(), {}, c.name(), 0};
        if (const auto dot = n.full.rfind('.'); dot != std::string::npos) {
            n.layer = n.full.substr(0, dot + 1);
            n.suffix = n.full.substr(dot + 1);
        }
        names.push_back(std::move(n));
    }
    std::stable_sort(names.begin(), names.end(),
                     [](const Name& a, const Name& b) { return a.layer < b.layer; });
    for (auto begin = names.begin(); begin != names.end();) {
        auto end = std::find_if(begin, names.end(),
                                [&](const Name& n) { return n.layer != begin->layer; });
        const auto has = [&](std::string_view s) {
            return std::any_of(begin, end, [&](const Name& n) { return sameLetters(n.suffix, s); });
        };
        const bool xyz = has("X") && (has("Y") || has("Z"));
        for (auto n = begin; n != end; ++n) n->rank = suffixRank(n->suffix, xyz);
        std::sort(begin, end, [](const Name& a, const Name& b) {
            return a.rank != b.rank ? a.rank < b.rank : a.suffix < b.suffix;
        });
        begin = end;
    }
    std::vector<std::string> out;
    for (Name& n : names) out.push_back(std::move(n.full));
    return out;
}

template <typename T>
std::string joined(std::initializer_list<T> values) {
    std::ostringstream s;
    s.precision(9);
    bool first = true;
    for (const T& v : values) {
        s << (first ? "" : " ") << v;
        first = false;
    }
    return s.str();
}

ExrAttribute attributeOf(const std::string& name, const Imf::Attribute& a) {
    ExrAttribute out{name, {}, std::nullopt};
    if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&a)) {
        out.text = s->value();
    } else if (const auto* i = dynamic_cast<const Imf::IntAttribute*>(&a)) {
        out.text = std::to_string(i->value());
        out.integer = i->value();
    } else if (const auto* f = dynamic_cast<const Imf::FloatAttribute*>(&a)) {
        out.text = joined({f->value()});
    } else if (const auto* d = dynamic_cast<const Imf::DoubleAttribute*>(&a)) {
        out.text = joined({d->value()});
    } else if (const auto* v = dynamic_cast<const Imf::V2fAttribute*>(&a)) {
        out.text = joined({v->value().x, v->value().y});
    } else if (const auto* vi = dynamic_cast<const Imf::V2iAttribute*>(&a)) {
        out.text = joined({vi->value().x, vi->value().y});
    } else if (const auto* b = dynamic_cast<const Imf::Box2iAttribute*>(&a)) {
        out.text = joined({b->value().min.x, b->value().min.y, b->value().max.x, b->value().max.y});
    } else {
        out.text = std::string("[") + a.typeName() + "]";
    }
    return out;
}

}  // namespace

const ExrAttribute* ExrLayout::find(std::string_view name) const {
    for (const ExrAttribute& a : attributes)
        if (a.name == name) return &a;
    return nullptr;
}

namespace {

// OpenEXRCore reports an error's details through a handler (by default it prints them); the
// handler keeps them for the thread whose call failed.
thread_local std::string t_coreMessage;
void keepCoreMessage(exr_const_context_t, exr_result_t, const char* message) {
    t_coreMessage = message ? message : "";
}
std::string coreFailure(exr_result_t result) {
    std::string message =
        t_coreMessage.empty() ? exr_get_default_error_message(result) : t_coreMessage;
    t_coreMessage.clear();
    return firstLine(message);
}

}  // namespace

// The header through OpenEXR's C++ library, the pixels through OpenEXRCore, whose chunks are
// decoded on TBB's threads straight into the caller's buffers: the C++ library's generic copy
// into a frame buffer takes twice as long for a 24-channel frame (docs/lab/image.md).
struct ExrInput::Files {
    std::unique_ptr<Imf::MultiPartInputFile> file;
    exr_context_t core = nullptr;
    std::vector<std::vector<std::string>> names;  // per part, its channels as the file names them
    ~Files() {
        if (core) exr_finish(&core);
    }
};

ExrInput::ExrInput(const std::filesystem::path& path)
    : m_file(path.string()), m_files(std::make_unique<Files>()) {
    checkRegularFile(path);
    if (!isExr(path)) {
        if (const DirectFormat* format = directFormatOf(path))
            throw Error(ErrorKind::Format,
                        std::string("expected an OpenEXR file, got a ") + format->name + " file",
                        m_file, "open");
        throw Error(ErrorKind::Format,
                    "not an image in OpenEXR's format (expected its magic number at byte 0)",
                    m_file, "open");
    }
    checkImageFile(path);

    try {
        m_files->file = std::make_unique<Imf::MultiPartInputFile>(m_file.c_str());
    } catch (const std::exception& e) {
        throw Error(ErrorKind::Format,
                    "not an image OpenEXR can read (" + firstLine(e.what()) + ")", m_file,
                    "header");
    }
    Imf::MultiPartInputFile& file = *m_files->file;
    const Imf::Header& first = file.header(0);
    const Imath::Box2i window = first.dataWindow();
    m_layout.x = window.min.x;
    m_layout.y = window.min.y;
    m_layout.width = window.max.x - window.min.x + 1;
    m_layout.height = window.max.y - window.min.y + 1;
    for (auto a = first.begin(); a != first.end(); ++a)
        m_layout.attributes.push_back(attributeOf(a.name(), a.attribute()));

    std::set<std::string> used;
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& header = file.header(p);
        const std::string where = partName(header, p);
        const std::string type =
            header.hasType() ? header.type()
                             : (header.hasTileDescription() ? Imf::TILEDIMAGE : Imf::SCANLINEIMAGE);
        if (Imf::isDeepData(type))
            throw Error(ErrorKind::Format,
                        "deep EXR data is not supported (expected flat pixels, one value per "
                        "channel)",
                        m_file, where);
        const Imath::Box2i w = header.dataWindow();
        if (w != window)
            throw Error(ErrorKind::Format,
                        "data window " + std::to_string(w.max.x - w.min.x + 1) + "x" +
                            std::to_string(w.max.y - w.min.y + 1) + " at (" +
                            std::to_string(w.min.x) + ", " + std::to_string(w.min.y) +
                            "); expected part 0's " + std::to_string(m_layout.width) + "x" +
                            std::to_string(m_layout.height) + " at (" + std::to_string(m_layout.x) +
                            ", " + std::to_string(m_layout.y) + ")",
                        m_file, where);
        const bool tiled = Imf::isTiled(type);
        ExrPart part{p, m_layout.channels(), 0, tiled ? int(header.tileDescription().xSize) : 0,
                     tiled ? int(header.tileDescription().ySize) : 0};
        for (auto c = header.channels().begin(); c != header.channels().end(); ++c)
            if (c.channel().xSampling != 1 || c.channel().ySampling != 1)
                throw Error(ErrorKind::Format,
                            "channel '" + std::string(c.name()) +
                                "' is subsampled; expected one value per pixel",
                            m_file, where);
        std::vector<std::string> names = presentedOrder(header.channels());
        if (names.empty())
            throw Error(ErrorKind::Format, "no channels; expected at least one", m_file, where);
        const std::string prefix = header.hasName() ? header.name() : std::string();
        for (const std::string& name : names) {
            std::string full = name;
            // A bare name ("R", "X") in a later part takes its part's name as its layer, as
            // writers that name each part after its layer expect.
            if (p > 0 && !prefix.empty() && name.find('.') == std::string::npos)
                full = prefix + "." + name;
            if (!used.insert(full).second)
                throw Error(ErrorKind::Format,
                            "channel '" + full +
                                "' is also in an earlier part; expected each "
                                "channel once",
                            m_file, where);
            m_layout.channelNames.push_back(full);
        }
        part.channels = int(names.size());
        m_layout.parts.push_back(part);
        m_files->names.push_back(std::move(names));
    }
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = keepCoreMessage;
    if (const exr_result_t r = exr_start_read(&m_files->core, m_file.c_str(), &init);
        r != EXR_ERR_SUCCESS)
        throw Error(ErrorKind::Format, "not an image OpenEXR can read (" + coreFailure(r) + ")",
                    m_file, "header");
}

ExrInput::~ExrInput() = default;

void ExrInput::read(const std::vector<ExrTarget>& targets) {
    // Every chunk (a block of scanlines or a tile of level 0) of every part with a wanted channel,
    // with its first pixel relative to the data window and its rows.
    struct Chunk {
        int part = 0;
        int tileX = 0, tileY = 0;  // a tile's column and row
        int x0 = 0, y0 = 0, rows = 0;
    };
    std::vector<Chunk> chunks;
    for (int p = 0; p < int(m_layout.parts.size()); ++p) {
        const ExrPart& part = m_layout.parts[std::size_t(p)];
        if (std::none_of(targets.begin(), targets.end(), [&](const ExrTarget& t) {
                return t.channel >= part.firstChannel &&
                       t.channel < part.firstChannel + part.channels;
            }))
            continue;
        if (part.tileHeight > 0) {
            const int columns = (m_layout.width + part.tileWidth - 1) / part.tileWidth;
            const int rows = (m_layout.height + part.tileHeight - 1) / part.tileHeight;
            for (int ty = 0; ty < rows; ++ty)
                for (int tx = 0; tx < columns; ++tx)
                    chunks.push_back(
                        {p, tx, ty, tx * part.tileWidth, ty * part.tileHeight, part.tileHeight});
        } else {
            int32_t lines = 1;
            exr_get_scanlines_per_chunk(m_files->core, p, &lines);
            lines = std::max(1, int(lines));
            for (int y = 0; y < m_layout.height; y += lines)
                chunks.push_back({p, 0, 0, 0, y, lines});
        }
    }

    // The failure of the first chunk in file order, whichever thread met it.
    std::mutex failureMutex;
    std::size_t failedChunk = std::numeric_limits<std::size_t>::max();
    std::string failure;
    exr_const_context_t core = m_files->core;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size()), [&](const auto& range) {
        exr_decode_pipeline_t decoder{};  // OpenEXR's initializer: all zero
        int decoderPart = -1;
        std::vector<const ExrTarget*> wanted;  // per channel of the decoder, in the file's order
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const Chunk& chunk = chunks[i];
            const ExrPart& part = m_layout.parts[std::size_t(chunk.part)];
            exr_chunk_info_t info{};
            exr_result_t r =
                part.tileHeight > 0
                    ? exr_read_tile_chunk_info(core, chunk.part, chunk.tileX, chunk.tileY, 0, 0,
                                               &info)
                    : exr_read_scanline_chunk_info(core, chunk.part, m_layout.y + chunk.y0, &info);
            if (r == EXR_ERR_SUCCESS && decoderPart == chunk.part) {
                r = exr_decoding_update(core, chunk.part, &info, &decoder);
            } else if (r == EXR_ERR_SUCCESS) {
                if (decoderPart >= 0) exr_decoding_destroy(core, &decoder);
                decoder = {};
                decoderPart = -1;
                r = exr_decoding_initialize(core, chunk.part, &info, &decoder);
                if (r == EXR_ERR_SUCCESS) {
                    decoderPart = chunk.part;
                    const std::vector<std::string>& names = m_files->names[std::size_t(chunk.part)];
                    wanted.assign(std::size_t(decoder.channel_count), nullptr);
                    for (int c = 0; c < decoder.channel_count; ++c) {
                        const auto name = std::find(names.begin(), names.end(),
                                                    std::string(decoder.channels[c].channel_name));
                        const int index = part.firstChannel + int(name - names.begin());
                        for (const ExrTarget& t : targets)
                            if (name != names.end() && t.channel == index)
                                wanted[std::size_t(c)] = &t;
                    }
                }
            }
            if (r == EXR_ERR_SUCCESS) {
                for (int c = 0; c < decoder.channel_count; ++c) {
                    exr_coding_channel_info_t& channel = decoder.channels[c];
                    const ExrTarget* t = wanted[std::size_t(c)];
                    channel.decode_to_ptr = t ? reinterpret_cast<uint8_t*>(t->first) +
                                                    std::size_t(chunk.y0) * t->yStride +
                                                    std::size_t(chunk.x0) * t->xStride
                                              : nullptr;
                    if (!t) continue;
                    channel.user_pixel_stride = int32_t(t->xStride);
                    channel.user_line_stride = int32_t(t->yStride);
                    channel.user_bytes_per_element = 4;
                    channel.user_data_type = EXR_PIXEL_FLOAT;
                }
                r = exr_decoding_choose_default_routines(core, chunk.part, &decoder);
                if (r == EXR_ERR_SUCCESS) r = exr_decoding_run(core, chunk.part, &decoder);
            }
            if (r != EXR_ERR_SUCCESS) {
                const std::string why = coreFailure(r);
                if (decoderPart >= 0) exr_decoding_destroy(core, &decoder);
                decoder = {};
                decoderPart = -1;
                std::lock_guard lock(failureMutex);
                if (i < failedChunk) {
                    failedChunk = i;
                    failure = why;
                }
            }
        }
        if (decoderPart >= 0) exr_decoding_destroy(core, &decoder);
    });
    if (failedChunk == std::numeric_limits<std::size_t>::max()) return;
    const Chunk& chunk = chunks[failedChunk];
    const int last = std::min(m_layout.height, chunk.y0 + chunk.rows) - 1;
    throw Error(
        ErrorKind::Format, "truncated or corrupt pixel data (" + failure + ")", m_file,
        (last == chunk.y0 ? "row " + std::to_string(chunk.y0)
                          : "rows " + std::to_string(chunk.y0) + "-" + std::to_string(last)) +
            (m_layout.parts.size() == 1 ? "" : " of part " + std::to_string(chunk.part)));
}

}  // namespace glint::detail
