// The registry of asset formats (asset_format.h) and the public list of them
// (glint/render/asset_formats.h).
#include <algorithm>
#include <cctype>

#include "glint/render/asset_formats.h"
#include "scene/asset_format.h"

namespace glint::render {

namespace detail {

// The built-in formats, in the order messages and dialogs list them: one line each, X(name), for
// the `const AssetFormat& <name>AssetFormat()` that the format's own file defines
// (docs/architecture.md, "Adding an asset format").
#define GLINT_ASSET_FORMATS(X) \
    X(obj)                     \
    X(gltf)

#define GLINT_DECLARE_ASSET_FORMAT(name) const AssetFormat& name##AssetFormat();
GLINT_ASSET_FORMATS(GLINT_DECLARE_ASSET_FORMAT)
#undef GLINT_DECLARE_ASSET_FORMAT

namespace {

std::vector<const AssetFormat*>& registry() {
#define GLINT_LIST_ASSET_FORMAT(name) &name##AssetFormat(),
    static std::vector<const AssetFormat*> formats{GLINT_ASSET_FORMATS(GLINT_LIST_ASSET_FORMAT)};
#undef GLINT_LIST_ASSET_FORMAT
    return formats;
}
#undef GLINT_ASSET_FORMATS

}  // namespace

const std::vector<const AssetFormat*>& assetFormatRegistry() {
    return registry();
}

const AssetFormat* findAssetFormat(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    for (const AssetFormat* format : registry())
        if (std::find(format->extensions.begin(), format->extensions.end(), ext) !=
            format->extensions.end())
            return format;
    return nullptr;
}

ScopedAssetFormat::ScopedAssetFormat(const AssetFormat& format) : m_format(&format) {
    registry().push_back(m_format);
}

ScopedAssetFormat::~ScopedAssetFormat() {
    auto& formats = registry();
    formats.erase(std::remove(formats.begin(), formats.end(), m_format), formats.end());
}

}  // namespace detail

std::vector<AssetFormatInfo> assetFormats() {
    std::vector<AssetFormatInfo> out;
    for (const detail::AssetFormat* format : detail::assetFormatRegistry())
        out.push_back({format->name, format->key, format->extensions});
    return out;
}

std::vector<std::string> assetExtensions() {
    std::vector<std::string> out;
    for (const detail::AssetFormat* format : detail::assetFormatRegistry())
        out.insert(out.end(), format->extensions.begin(), format->extensions.end());
    return out;
}

bool isAssetFile(const std::filesystem::path& path) {
    return detail::findAssetFormat(path) != nullptr;
}

}  // namespace glint::render
