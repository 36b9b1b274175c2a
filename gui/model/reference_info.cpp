#include "model/reference_info.h"

#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>

#include <cstdio>
#include <exception>

#include "glint/denoise/bank.h"
#include "model/session_state.h"

namespace glint::studio {

namespace {

constexpr const char* kReferencePrefix = "reference/";
constexpr const char* kSourceRendered = "rendered";
constexpr const char* kSourceFile = "file";

std::string identityText(std::uint64_t v) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

}  // namespace

void writeReferenceState(const ReferenceInfo& info, std::map<std::string, std::string>& state) {
    const std::string prefix = kReferencePrefix;
    if (info.source == ReferenceInfo::Source::File) {
        state[prefix + "source"] = kSourceFile;
        state[prefix + "file"] = info.file;
        state[prefix + "identity"] = identityText(info.identity);
        return;
    }
    state[prefix + "source"] = kSourceRendered;
    state[prefix + "scene"] = info.scene;
    state[prefix + "camera"] = info.camera;
    // The look and settings under the keys a session's own look and settings use.
    std::map<std::string, std::string> own;
    writeDocumentState(info.look, info.settings, own);
    for (const auto& [key, value] : own) state[prefix + key] = value;
}

std::optional<ReferenceInfo> readReferenceState(const std::map<std::string, std::string>& state,
                                                const std::vector<render::LookItem>& look) {
    const std::string prefix = kReferencePrefix;
    std::map<std::string, std::string> own;
    for (auto it = state.lower_bound(prefix); it != state.end() && it->first.starts_with(prefix);
         ++it)
        own[it->first.substr(prefix.size())] = it->second;
    auto get = [&](const char* key) {
        const auto it = own.find(key);
        return it == own.end() ? std::string() : it->second;
    };
    ReferenceInfo info;
    const std::string source = get("source");
    if (source == kSourceFile) {
        info.source = ReferenceInfo::Source::File;
        info.file = get("file");
        try {
            info.identity = std::stoull(get("identity"), nullptr, 16);
        } catch (const std::exception&) {
            return std::nullopt;  // an identity that cannot be checked: not used
        }
        return info.file.empty() ? std::nullopt : std::optional<ReferenceInfo>(info);
    }
    if (source != kSourceRendered) return std::nullopt;
    info.source = ReferenceInfo::Source::Rendered;
    info.scene = get("scene");
    info.camera = get("camera");
    info.look = readLook(own, look);
    try {
        info.settings = readSettings(own, info.settings);
    } catch (const std::exception&) {
        // What it was rendered with is a description only: the pixels are the reference.
    }
    return info;
}

std::string sceneCamera(const std::filesystem::path& path) {
    if (path.extension() != ".json") return {};
    QFile file(QString::fromStdString(path.string()));
    if (!file.open(QIODevice::ReadOnly)) return {};
    const QJsonObject camera =
        QJsonDocument::fromJson(file.readAll()).object().value(QStringLiteral("camera")).toObject();
    return camera.isEmpty() ? std::string()
                            : QJsonDocument(camera).toJson(QJsonDocument::Compact).toStdString();
}

std::uint64_t referenceIdentity(const FrameBuffers& frame) {
    return denoise::hashFrame(frame);
}

}  // namespace glint::studio
