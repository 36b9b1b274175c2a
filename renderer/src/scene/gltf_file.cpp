// Reading a glTF file (gltf_file.h): the binary container's layout, tinygltf's file access and
// its error text turned into Glint's errors.
#include "scene/gltf_file.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "scene/gltf_buffers.h"
#include "scene/gltf_document.h"
#include "scene/input_file.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

namespace {

constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"

[[noreturn]] void failFile(const fs::path& file, const std::string& place, const std::string& what,
                           ErrorKind kind = ErrorKind::Format) {
    throw Error(kind, what, file.string(), place);
}

/// Reads `count` bytes of `path` from `offset` into `out` in one read; false when the file
/// cannot be opened or is shorter.
bool readBytes(const fs::path& path, std::uint64_t offset, std::uint64_t count,
               std::vector<unsigned char>& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return false;
    out.resize(std::size_t(count));
    in.seekg(std::streamoff(offset));
    return bool(in.read(reinterpret_cast<char*>(out.data()), std::streamsize(count)));
}

/// Where a .glb's chunks are: the JSON chunk and, when there is one, the BIN chunk.
struct GlbLayout {
    std::uint64_t jsonOffset = 0, jsonSize = 0;
    std::uint64_t binOffset = 0, binSize = 0;
    bool hasBin = false;
};

/// Refuses a .gltf or .glb whose text starts (after white space and a UTF-8 byte-order mark)
/// with '<': an HTML or XML page, most often a web page saved under the asset's name, which the
/// JSON parser would report as an invalid literal followed by the page's first bytes (and the
/// .glb reader as a wrong magic).
void refuseMarkup(const fs::path& file, const std::vector<unsigned char>& text, bool binary) {
    const bool bom = text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF;
    std::size_t at = bom ? 3 : 0;
    std::size_t line = 1, column = 1;
    for (; at < text.size() && std::isspace(text[at]); ++at, ++column)
        if (text[at] == '\n') ++line, column = 0;
    if (at < text.size() && text[at] == '<')
        failFile(file, "line " + std::to_string(line) + ", column " + std::to_string(column),
                 std::string(binary ? "not a binary glTF" : "malformed JSON") +
                     ": the file is HTML or XML, not glTF (a web page saved under the asset's "
                     "name?)");
}

/// Checks a binary glTF's header and chunk structure (glTF 2.0 spec, "Binary glTF Layout") from
/// the file, so that a truncated or damaged file is named with its byte rather than by
/// tinygltf's text.
GlbLayout glbLayout(const fs::path& file, std::uint64_t fileSize) {
    std::ifstream in(file, std::ios::binary);
    if (!in) failFile(file, "", "cannot open the glTF file", ErrorKind::Io);
    auto read8 = [&](std::uint64_t offset, unsigned char* out) {
        in.seekg(std::streamoff(offset));
        return bool(in.read(reinterpret_cast<char*>(out), 8));
    };
    if (fileSize < 12)
        failFile(file, "header",
                 "truncated binary glTF: " + std::to_string(fileSize) +
                     " bytes, fewer than the 12-byte header");
    unsigned char h[12];
    if (!in.read(reinterpret_cast<char*>(h), 12))
        failFile(file, "header", "cannot read the header", ErrorKind::Io);
    if (le32(&h[0]) != kGlbMagic) {
        // A web page saved under a .glb's name is named as one, as for a .gltf.
        std::vector<unsigned char> head;
        if (readBytes(file, 0, std::min<std::uint64_t>(fileSize, 4096), head))
            refuseMarkup(file, head, true);
        failFile(file, "byte 0", "wrong magic: not a binary glTF (expected the bytes 'glTF')");
    }
    if (const std::uint32_t version = le32(&h[4]); version != 2)
        failFile(file, "header",
                 "binary glTF version " + std::to_string(version) + "; Glint reads version 2");
    const std::uint64_t length = le32(&h[8]);
    if (length != fileSize)
        failFile(
            file, "header",
            (length > fileSize ? "truncated binary glTF: the header says " : "the header says ") +
                std::to_string(length) + " bytes, the file has " + std::to_string(fileSize));
    GlbLayout layout;
    std::uint64_t offset = 12;
    for (int chunk = 0; offset < length; ++chunk) {
        const std::string place =
            "chunk " + std::to_string(chunk) + " (byte " + std::to_string(offset) + ")";
        unsigned char c[8];
        if (length - offset < 8 || !read8(offset, c))
            failFile(file, place, "truncated chunk header");
        const std::uint64_t size = le32(&c[0]);
        const std::uint32_t type = le32(&c[4]);
        if (size > length - offset - 8)
            failFile(file, place,
                     "a chunk of " + std::to_string(size) +
                         " bytes goes past the end of the file (truncated)");
        if (chunk == 0 && type != kChunkJson)
            failFile(file, place, "the first chunk must be the JSON chunk");
        if (chunk == 1 && type != kGlbChunkBin)
            failFile(file, place, "the second chunk must be the BIN chunk");
        if (chunk == 0) layout.jsonOffset = offset + 8, layout.jsonSize = size;
        if (chunk == 1) layout.binOffset = offset + 8, layout.binSize = size, layout.hasBin = true;
        offset += 8 + size;
    }
    if (offset == 12) failFile(file, "header", "the file has no JSON chunk");
    return layout;
}

/// tinygltf's image callback: keeps a data URI's encoded bytes for Glint's own reader. Images in
/// files and bufferViews are read later from where they are, with their bounds checked.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
    if (image->bufferView < 0 && image->uri.empty() && bytes && size > 0)
        image->image.assign(bytes, bytes + size);
    return true;
}

// File access for tinygltf: no search of the current folder (tinygltf tries "./name" after the
// asset's folder), no devices or pipes.
bool fileExists(const std::string& path, void*) {
    if (path.rfind("./", 0) == 0) return false;
    std::error_code ec;
    return fs::is_regular_file(path, ec);
}
std::string expandFilePath(const std::string& path, void*) {
    return path;
}
bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void*) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) {
        if (err) *err += "not a regular file: " + path + "\n";
        return false;
    }
    if (!readBytes(path, 0, fs::file_size(path, ec), *out)) {
        if (err) *err += "cannot read " + path + "\n";
        return false;
    }
    return true;
}
bool writeWholeFile(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
    return false;
}

/// The glTF place a tinygltf message names ("buffer[0]" → "buffers[0]"), or "".
std::string placeOf(const std::string& message) {
    for (std::size_t open = message.find('['); open != std::string::npos;
         open = message.find('[', open + 1)) {
        std::size_t start = open;
        while (start > 0 && std::isalpha(static_cast<unsigned char>(message[start - 1]))) --start;
        std::size_t close = open + 1;
        while (close < message.size() && std::isdigit(static_cast<unsigned char>(message[close])))
            ++close;
        if (start == open || close == open + 1 || close >= message.size() || message[close] != ']')
            continue;
        std::string name = message.substr(start, open - start);
        if (name.back() != 's') name += 's';
        return name + message.substr(open, close - open + 1);
    }
    return {};
}

/// The text after `prefix` in `text` when `text` holds it (from its start when `anchored`).
std::optional<std::string> after(const std::string& text, const std::string& prefix,
                                 bool anchored) {
    const std::size_t at = text.find(prefix);
    if (at == std::string::npos || (anchored && at != 0)) return std::nullopt;
    return text.substr(at + prefix.size());
}

/// Throws the first line of tinygltf's error text as one Error with the glTF place it names,
/// rephrased where tinygltf's words are not a user's (JSON parser exceptions, whole data URIs).
[[noreturn]] void readerFailed(const fs::path& file, const std::string& err) {
    std::string first = err.substr(0, err.find('\n'));
    while (!first.empty() && (first.back() == '.' || first.back() == ' ')) first.pop_back();
    // "parse error at line L, column C: what" (nlohmann-json's exception text).
    if (const auto rest = after(first, "parse error at line ", false)) {
        const std::size_t comma = rest->find(", column "), colon = rest->find(": ");
        if (comma != std::string::npos && colon != std::string::npos && comma < colon)
            failFile(file,
                     "line " + rest->substr(0, comma) + ", column " +
                         rest->substr(comma + 9, colon - comma - 9),
                     "malformed JSON: " + rest->substr(colon + 2));
    }
    if (const auto name = after(first, "File not found : ", true)) {
        if (const auto problem = undecodedDataUri(*name)) failFile(file, "buffers", *problem);
        failFile(file, "buffers", "buffer file '" + *name + "' not found", ErrorKind::Io);
    }
    // "File size mismatch : NAME, requestedBytes N, but got M".
    if (const auto rest = after(first, "File size mismatch : ", true)) {
        const std::size_t requested = rest->find(", requestedBytes "),
                          got = rest->find(", but got ");
        if (requested != std::string::npos && got != std::string::npos && requested < got)
            failFile(file, "buffers",
                     "buffer file '" + rest->substr(0, requested) + "' has " +
                         rest->substr(got + 10) + " bytes, its byteLength says " +
                         rest->substr(requested + 17, got - requested - 17));
    }
    // "Failed to decode 'uri' for image[N] name = [...]" (an image's) or "... in Buffer".
    if (const auto rest = after(first, "Failed to decode 'uri' for image[", true)) {
        const std::string index = rest->substr(0, rest->find(']'));
        failFile(file, "images[" + index + "].uri", "the image's data URI is not valid base64");
    }
    if (first.rfind("Failed to decode 'uri'", 0) == 0)
        failFile(file, "buffers", "a buffer's data URI is not base64 of its byteLength bytes");
    if (first.empty()) first = "unreadable glTF";
    if (first.size() > 200) first = first.substr(0, 200) + "...";
    failFile(file, placeOf(first), "cannot read the glTF: " + first);
}

/// The extensionsRequired of a document tinygltf could not read, as strings (non-strings
/// skipped); empty when the document is not a JSON object.
std::vector<std::string> requiredExtensions(const nlohmann::json& doc) {
    std::vector<std::string> out;
    if (!doc.is_object() || !doc.contains("extensionsRequired") ||
        !doc["extensionsRequired"].is_array())
        return out;
    for (const nlohmann::json& e : doc["extensionsRequired"])
        out.push_back(e.is_string() ? e.get<std::string>() : std::string());
    return out;
}

/// A buffer uri as tinygltf decodes it before looking for the file (dlib's urldecode: "+" is a
/// space, "%XY" a byte, a non-hex digit counting as 0).
std::string bufferUriAsTinygltf(const std::string& uri) {
    auto hex = [](unsigned char c) -> unsigned {
        return c >= '0' && c <= '9'   ? unsigned(c - '0')
               : c >= 'a' && c <= 'f' ? unsigned(c - 'a' + 10)
               : c >= 'A' && c <= 'F' ? unsigned(c - 'A' + 10)
                                      : 0u;
    };
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && uri.size() > i + 2) {
            out += char(hex(static_cast<unsigned char>(uri[i + 1])) << 4 |
                        hex(static_cast<unsigned char>(uri[i + 2])));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

/// The uri a buffer Glint reads from its file has in the document tinygltf parses (with
/// byteLength 1): one zero byte as a data URI, which tinygltf decodes instead of reading the
/// buffer.
constexpr const char* kFileBufferUri = "data:application/octet-stream;base64,AA==";

/// The most buffer files one asset holds open while it is read; tinygltf reads any further ones
/// whole, so that an asset of many small buffers leaves descriptors for its textures.
constexpr std::size_t kMaxOpenBufferFiles = 64;

/// Opens the buffers of `buffersJson` (buffersOf) that Glint reads from their files: a .glb's
/// BIN chunk (buffer 0 without a uri, when `glb` has a BIN chunk) and buffer files (a uri that is
/// not a data URI) of exactly their byteLength, at most kMaxOpenBufferFiles. A buffer not opened
/// is left to tinygltf, which reads it as before and reports what is wrong with it. Returns the
/// indices opened.
std::vector<std::size_t> openBufferFiles(const fs::path& path, std::uint64_t fileSize,
                                         const std::string& baseDir, const GlbLayout* glb,
                                         const nlohmann::json& buffersJson, GltfBuffers& buffers) {
    std::vector<std::size_t> opened;
    for (std::size_t i = 0; i < buffersJson.size() && opened.size() < kMaxOpenBufferFiles; ++i) {
        const nlohmann::json& b = buffersJson[i];
        if (!b.is_object() || !b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
            continue;
        const std::uint64_t byteLength = b["byteLength"].get<std::uint64_t>();
        if (byteLength == 0) continue;
        std::unique_ptr<BufferFile> file;
        if (!b.contains("uri") && glb && glb->hasBin && i == 0) {
            if (byteLength > glb->binSize)
                failFile(path, "buffers[0].byteLength",
                         "is " + std::to_string(byteLength) + " bytes, more than the " +
                             std::to_string(glb->binSize) + " bytes of the BIN chunk");
            file = BufferFile::open(path, fileSize, glb->binOffset, byteLength);
        } else if (b.contains("uri") && b["uri"].is_string()) {
            const std::string& uri = b["uri"].get_ref<const std::string&>();
            if (uri.rfind("data:", 0) == 0) continue;  // tinygltf's, decoded or named by it
            const std::string name = bufferUriAsTinygltf(uri);
            if (name.empty()) continue;
            // Where tinygltf looks for it (its JoinPath of the asset's folder and the name).
            const std::string where = baseDir.empty()         ? name
                                      : baseDir.back() == '/' ? baseDir + name
                                                              : baseDir + "/" + name;
            if (const InputKind kind = inputKind(where);
                kind == InputKind::Folder || kind == InputKind::Special)
                failFile(path, "buffers[" + std::to_string(i) + "].uri",
                         "buffer file '" + name + "' " + notARegularFile(kind, "a buffer file"),
                         ErrorKind::Io);
            std::error_code ec;
            if (fs::is_regular_file(where, ec) && fs::file_size(where, ec) == byteLength && !ec)
                file = BufferFile::open(where, byteLength, 0, byteLength);
        }
        if (!file) continue;
        buffers.setFile(i, std::move(file));
        opened.push_back(i);
    }
    return opened;
}

}  // namespace

std::optional<std::pair<std::size_t, std::string>> unreadRequiredExtension(
    const std::vector<std::string>& required) {
    std::string list;
    for (const char* e : kReadGltfExtensions) list += (list.empty() ? "" : ", ") + std::string(e);
    for (std::size_t i = 0; i < required.size(); ++i) {
        bool read = false;
        for (const char* e : kReadGltfExtensions) read = read || required[i] == e;
        if (!read && !required[i].empty())
            return std::pair{i, "the asset requires extension " + required[i] +
                                    ", which Glint does not read (it reads " + list + ")"};
    }
    return std::nullopt;
}

std::optional<std::string> undecodedDataUri(const std::string& uri) {
    // URI schemes are case-insensitive (RFC 3986, 3.1).
    if (uri.size() < 5) return std::nullopt;
    std::string scheme = uri.substr(0, 5);
    std::transform(scheme.begin(), scheme.end(), scheme.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (scheme != "data:") return std::nullopt;
    const std::size_t comma = uri.find(',');
    std::string header = uri.substr(0, std::min<std::size_t>(comma, 100));
    if (comma == std::string::npos || comma > 100) header += "...";
    const std::string base64 = ";base64";
    const bool isBase64 = comma != std::string::npos && comma >= base64.size() &&
                          uri.compare(comma - base64.size(), base64.size(), base64) == 0;
    if (!isBase64)
        return "the data URI '" + header +
               ",' is not base64-encoded: glTF data URIs must end their header with ';base64,'";
    return "the data URI '" + header +
           ",' has a media type Glint does not decode (it reads application/octet-stream, "
           "application/gltf-buffer, image/png and image/jpeg)";
}

void readGltfFile(const fs::path& path, tinygltf::Model& model, GltfBuffers& buffers) {
    std::error_code ec;  // odd paths (too long...) are reported, not thrown
    const std::uint64_t size = fs::file_size(path, ec);
    if (ec) failFile(path, "", "cannot read the glTF file: " + ec.message(), ErrorKind::Io);
    if (size >= std::numeric_limits<unsigned int>::max())
        failFile(path, "", "the file is 4 GB or larger (tinygltf reads up to 4 GB)");
    std::string extension = path.extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    std::vector<unsigned char> bytes;
    if (!readBytes(path, 0, std::min<std::uint64_t>(size, 4), bytes))
        failFile(path, "", "cannot open the glTF file", ErrorKind::Io);
    const bool binary = bytes.size() >= 4 && le32(bytes.data()) == kGlbMagic;

    tinygltf::TinyGLTF reader;
    reader.SetImageLoader(&keepEncodedImage, nullptr);
    reader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, &writeWholeFile, nullptr});
    std::string err, warnings;
    const std::string baseDir = fs::absolute(path, ec).parent_path().string();
    // The document's text: a .gltf's, or a .glb's JSON chunk.
    std::optional<GlbLayout> layout;
    if (binary || extension == ".glb") {
        layout = glbLayout(path, size);
        if (!readBytes(path, layout->jsonOffset, layout->jsonSize, bytes))
            failFile(path, "", "cannot read the JSON chunk", ErrorKind::Io);
    } else if (!readBytes(path, 0, size, bytes)) {
        failFile(path, "", "cannot open the glTF file", ErrorKind::Io);
    } else {
        refuseMarkup(path, bytes, false);
    }
    // The document's JSON checked first: its nesting before any parser recurses through it, then
    // the values tinygltf would read leniently (gltf_document.h).
    GltfText text;
    text.text = {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
    if (layout) {
        text.binary = true;
        text.chunkOffset = layout->jsonOffset;
        text.hasBin = layout->hasBin && layout->binSize > 0;
    }
    checkGltfNesting(text, path);
    nlohmann::json buffersJson = nlohmann::json::array();
    {
        nlohmann::json checked = parseGltfDocument(text, path);
        checkGltfDocument(checked, text, path);
        if (checked.contains("buffers") && checked["buffers"].is_array())
            buffersJson = std::move(checked["buffers"]);
    }  // the rest of the checked document is freed before tinygltf parses its own
    // Open the buffers Glint reads from their files, and give tinygltf the document with each of
    // those buffers replaced by a one-byte data URI, so that it parses the document without
    // reading them. A .glb is read that way only when every buffer without a uri (which tinygltf
    // fills from the BIN chunk) is opened; otherwise, like any document with no buffer file, it
    // is given to tinygltf as it is, so that its reading and errors are tinygltf's.
    buffers = GltfBuffers(path);
    std::vector<std::size_t> opened =
        openBufferFiles(path, size, baseDir, layout ? &*layout : nullptr, buffersJson, buffers);
    bool uriLessUnopened = false;
    for (std::size_t i = 0; i < buffersJson.size(); ++i)
        uriLessUnopened =
            uriLessUnopened || (buffersJson[i].is_object() && !buffersJson[i].contains("uri") &&
                                std::find(opened.begin(), opened.end(), i) == opened.end());
    nlohmann::json doc;
    if (!opened.empty() && !(layout && uriLessUnopened))
        doc = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    std::string json;  // the rewritten document, when buffers are read from their files
    if (doc.is_object()) {
        for (std::size_t i : opened) {
            doc["buffers"][i]["uri"] = kFileBufferUri;
            doc["buffers"][i]["byteLength"] = 1;
        }
        json = doc.dump();
    } else {
        buffers = GltfBuffers(path);  // tinygltf reads every buffer
        if (layout && !readBytes(path, 0, size, bytes))
            failFile(path, "", "cannot open the glTF file", ErrorKind::Io);
    }
    bool ok = false;
    try {
        if (!json.empty())
            ok = reader.LoadASCIIFromString(&model, &err, &warnings, json.data(),
                                            unsigned(json.size()), baseDir);
        else if (layout)
            ok = reader.LoadBinaryFromMemory(&model, &err, &warnings, bytes.data(),
                                             unsigned(bytes.size()), baseDir);
        else
            ok = reader.LoadASCIIFromString(&model, &err, &warnings,
                                            reinterpret_cast<const char*>(bytes.data()),
                                            unsigned(bytes.size()), baseDir);
    } catch (const std::exception& e) {
        err = e.what();
    }
    if (!ok) {
        // An asset that requires an extension Glint does not read (Draco, meshopt) fails in
        // tinygltf for want of what the extension holds: name the extension, not the symptom.
        const auto text =
            bytes.begin() + std::ptrdiff_t(layout && json.empty() ? layout->jsonOffset : 0);
        const nlohmann::json document =
            !json.empty() ? nlohmann::json::parse(json, nullptr, false)
            : layout ? nlohmann::json::parse(text, text + std::ptrdiff_t(layout->jsonSize), nullptr,
                                             false)
                     : nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
        if (const auto unread = unreadRequiredExtension(requiredExtensions(document)))
            failFile(path, "extensionsRequired[" + std::to_string(unread->first) + "]",
                     unread->second);
        readerFailed(path, err);
    }
    if (model.asset.version.rfind("2.", 0) != 0)
        failFile(path, "asset.version", "is '" + model.asset.version + "'; Glint reads glTF 2.x");
    buffers.bind(model);
}

}  // namespace glint::render::detail
