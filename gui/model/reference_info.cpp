#include "model/reference_info.h"

#include <QFile>
#include <QJsonDocument>
#include <QJsonObject>

#include <algorithm>
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

bool sameLook(const std::vector<render::LookItem>& a, const std::vector<render::LookItem>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].name != b[i].name || a[i].properties.size() != b[i].properties.size())
            return false;
        for (std::size_t k = 0; k < a[i].properties.size(); ++k)
            if (a[i].properties[k].name != b[i].properties[k].name ||
                a[i].properties[k].value != b[i].properties[k].value)
                return false;
    }
    return true;
}

bool sameSceneFile(const std::string& a, const std::string& b) {
    if (a.empty() || b.empty()) return false;
    const std::filesystem::path pa = std::filesystem::path(a).lexically_normal();
    const std::filesystem::path pb = std::filesystem::path(b).lexically_normal();
    if (pa == pb) return true;
    if (pa.is_absolute() == pb.is_absolute()) return false;
    // The relative one's components (without a leading ".") end the absolute one.
    const std::filesystem::path& rel = pa.is_absolute() ? pb : pa;
    const std::filesystem::path& abs = pa.is_absolute() ? pa : pb;
    std::vector<std::filesystem::path> r(rel.begin(), rel.end()), f(abs.begin(), abs.end());
    while (!r.empty() && r.front() == ".") r.erase(r.begin());
    if (r.empty() || r.size() > f.size() ||
        std::any_of(r.begin(), r.end(), [](const auto& c) { return c == ".."; }))
        return false;
    return std::equal(r.rbegin(), r.rend(), f.rbegin());
}

ReferenceMismatch referenceMismatch(const ReferenceInfo& reference, const ReferenceTarget& now) {
    if ((reference.source == ReferenceInfo::Source::File && reference.scene.empty()) ||
        now.scene.empty())
        return ReferenceMismatch::Unknown;
    if (!sameSceneFile(reference.scene, now.scene)) return ReferenceMismatch::Scene;
    // A file of glint-render shows the scene file as it is: its own look and camera.
    const bool rendered = reference.source == ReferenceInfo::Source::Rendered;
    if (!sameLook(rendered ? reference.look : now.fileLook, now.look))
        return ReferenceMismatch::Look;
    if (rendered && reference.camera != now.camera) return ReferenceMismatch::Camera;
    return ReferenceMismatch::None;
}

std::uint64_t referenceSeed(std::uint64_t seed) {
    return (seed ^ 0x2545F4914F6CDD1DULL) & ((std::uint64_t(1) << 63) - 1);
}

std::uint64_t referenceIdentity(const FrameBuffers& frame) {
    return denoise::hashFrame(frame);
}

}  // namespace glint::studio
