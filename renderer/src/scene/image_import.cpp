// Textures and environment images: read through glint::readImage, linearised, checked; the
// loader's texture table (Loader::loadTexture): untiled files and embedded images held in
// memory, tiled files opened in the scene's TextureStore.
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <tuple>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "scene/input_file.h"
#include "scene/loader.h"

namespace glint::render::detail {

namespace fs = std::filesystem;

Image scaledRgb(const Image& source, float scale, const std::string& what,
                const std::filesystem::path& sceneFile, const std::string& where) {
    if (source.width() < 1 || source.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", sceneFile.string(), where);
    Image out(source.width(), source.height(), 3);
    for (int y = 0; y < source.height(); ++y)
        for (int x = 0; x < source.width(); ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = source(x, y, source.channels() >= 3 ? c : 0) * scale;
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")" +
                                    (scale != 1.0f ? " after scaling by " + std::to_string(scale)
                                                   : std::string()),
                                sceneFile.string(), where);
                out(x, y, c) = v;
            }
    return out;
}

Image readLinearRgb(const std::filesystem::path& image, float scale, const std::string& what,
                    const std::filesystem::path& sceneFile, const std::string& where) {
    requireRegularFile(image, what, "an image file", sceneFile.string(), where);
    const Image raw = readImage(image, true);
    try {
        return scaledRgb(raw, scale, what, sceneFile, where);
    } catch (const Error& e) {
        // Name the image itself as the file.
        throw Error(e.kind(), e.message(), image.string(), where);
    }
}

Image textureRgba(const Image& raw, const std::string& what, const std::filesystem::path& file,
                  const std::string& where) {
    if (raw.width() < 1 || raw.height() < 1)
        throw Error(ErrorKind::Format, what + " is empty", file.string(), where);
    const int n = raw.channels();
    // Grey, grey + alpha, RGB or RGBA → RGBA (alpha 1 where there is none).
    const int rgb[3] = {0, n >= 3 ? 1 : 0, n >= 3 ? 2 : 0};
    const int alpha = n == 2 ? 1 : (n >= 4 ? 3 : -1);
    Image out(raw.width(), raw.height(), 4);
    for (int y = 0; y < raw.height(); ++y)
        for (int x = 0; x < raw.width(); ++x) {
            for (int c = 0; c < 4; ++c) {
                const float v = c < 3 ? raw(x, y, rgb[c]) : (alpha >= 0 ? raw(x, y, alpha) : 1.0f);
                // A NaN/Inf/negative value would poison every path that reaches it.
                if (!std::isfinite(v) || v < 0.0f || v > kMaxRadiance)
                    throw Error(ErrorKind::Format,
                                what + " has a negative, non-finite or too large (above " +
                                    std::to_string(kMaxRadiance) + ") value at pixel (" +
                                    std::to_string(x) + ", " + std::to_string(y) + ")",
                                file.string(), where);
                out(x, y, c) = v;
            }
        }
    return out;
}

int Loader::loadTexture(const fs::path& path, const std::string& where) {
    Texture source;
    source.path = path.is_absolute() ? path : m_dir / path;
    return loadTexture(source, where);
}

int Loader::loadTexture(const Texture& source, const std::string& where) {
    const auto key = std::tuple{source.path, int(source.use), int(source.wrapS), int(source.wrapT)};
    const auto it = m_textureIndex.find(key);
    if (it != m_textureIndex.end()) return it->second;
    Texture tex = source;
    const bool linearize = source.use == TextureUse::Color;
    if (source.bytes) {
        try {
            tex.image = textureRgba(readImage(*source.bytes, source.path.string(), linearize),
                                    "texture", source.path, where);
        } catch (const Error& e) {
            throw Error(e.kind(), e.message(), source.path.string(),
                        where + (e.where().empty() ? "" : " (" + e.where() + ")"));
        }
    } else {
        requireRegularFile(source.path, "texture", "an image file", m_reader.file().string(),
                           where);
        const int file = openTextureFile(source.path, linearize, where);
        m_scene.addInput(source.path);
        if (!m_scene.textureStore->info(file).tiled) {
            // An untiled file (PNG, JPEG, scanline EXR) has no random access: it is read
            // whole, decoded to linear and looked up in memory, exactly and fast, as an
            // embedded image is (docs/assets.md, "Textures").
            tex.image =
                textureRgba(readImage(source.path, linearize), "texture", source.path, where);
        } else {
            tex.file = file;
            tex.store = m_scene.textureStore;
            tex.decodeSrgb = linearize && m_scene.textureStore->info(tex.file).srgb;
            tex.contentHash = m_scene.textureStore->contentHash(tex.file);
            // Reading the resident levels reads the file's small MIP levels: a file damaged
            // there fails now.
            tex.readLevels();
            // The store's tile cache makes room for the resident levels.
            m_scene.textureStore->addResidentBytes(tex.levels.residentBytes());
            m_scene.textureStore->throwIfFailed();
        }
    }
    m_scene.textures.push_back(std::move(tex));
    m_textureIndex[key] = int(m_scene.textures.size()) - 1;
    return int(m_scene.textures.size()) - 1;
}

int Loader::openTextureFile(const fs::path& path, bool linearize, const std::string& where) {
    if (!m_scene.textureStore) m_scene.textureStore = std::make_shared<TextureStore>();
    TextureStore& store = *m_scene.textureStore;
    checkImageFile(path);  // before OpenImageIO allocates what a damaged header claims
    int file = -1;
    try {
        file = store.open(path, m_reader.file(), where);
    } catch (const Error&) {
        // glint::readImage says what is wrong with the file as every other image reader of
        // Glint does; OIIO's own reason when it reads what the TextureSystem could not.
        (void)readImage(path, linearize);
        throw;
    }
    return file;
}

}  // namespace glint::render::detail
