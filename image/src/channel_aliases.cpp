#include "channel_aliases.h"

#include <algorithm>
#include <array>
#include <optional>
#include <string_view>

#include "glint/image/error.h"

namespace glint::detail {

namespace {

/// One way of filling a layer: the file channels that hold its channels, in order.
struct Candidate {
    Layer layer;
    std::vector<std::string> names;
    bool perSampleVariance = false;
};

std::vector<std::string> withSuffixes(const std::string& prefix, std::string_view suffixes) {
    std::vector<std::string> out;
    for (char s : suffixes) out.push_back(prefix + s);
    return out;
}

/// Glint's own names (the table of docs/image.md), built from the layer descriptions.
std::vector<Candidate> glintCandidates() {
    std::vector<Candidate> out;
    for (int l = 0; l < kLayerCount; ++l) {
        Candidate c{Layer(l), {}};
        for (int ch = 0; ch < layerInfo(Layer(l)).channels; ++ch)
            c.names.push_back(channelName(Layer(l), ch));
        out.push_back(std::move(c));
    }
    return out;
}

/// Blender/Cycles multilayer names; `prefix` is the view layer ("ViewLayer.") or empty.
std::vector<Candidate> cyclesCandidates(const std::string& prefix) {
    return {
        {Layer::Color, withSuffixes(prefix + "Combined.", "RGB")},
        {Layer::Color, withSuffixes("", "RGB")},
        {Layer::Albedo, withSuffixes(prefix + "Denoising Albedo.", "RGB")},
        {Layer::Normal, withSuffixes(prefix + "Denoising Normal.", "XYZ")},
        {Layer::Depth, {prefix + "Denoising Depth.Z"}},
        // With denoising on, Combined is the denoised colour and Noisy Image the render's.
        {Layer::Noisy, withSuffixes(prefix + "Noisy Image.", "RGB")},
    };
}

/// pbrt-v4 GBufferFilm names. Ns (shading normal) is preferred over N, as Glint's normal is the
/// shading normal; depth is P.Z because pbrt's P is in camera space, whose z is the view axis.
std::vector<Candidate> pbrtCandidates() {
    return {
        {Layer::Color, withSuffixes("", "RGB")},
        {Layer::Variance, withSuffixes("Variance.", "RGB"), true},
        {Layer::Albedo, withSuffixes("Albedo.", "RGB")},
        {Layer::Normal, withSuffixes("Ns.", "XYZ")},
        {Layer::Normal, withSuffixes("N.", "XYZ")},
        {Layer::Position, withSuffixes("P.", "XYZ")},
        {Layer::Depth, {"P.Z"}},
    };
}

/// Mitsuba 3 AOV integrator names.
std::vector<Candidate> mitsubaCandidates() {
    return {
        {Layer::Color, withSuffixes("", "RGB")},
        {Layer::Albedo, withSuffixes("albedo.", "RGB")},
        {Layer::Normal, withSuffixes("sh_normal.", "XYZ")},
        {Layer::Depth, {"depth.T"}},
    };
}

bool startsWith(std::string_view s, std::string_view p) {
    return s.substr(0, p.size()) == p;
}

bool endsWith(std::string_view s, std::string_view p) {
    return s.size() >= p.size() && s.substr(s.size() - p.size()) == p;
}

/// True for a channel only Glint's convention uses.
bool isGlintOnly(const std::string& name) {
    for (std::string_view p : {"variance.", "albedoVariance.", "normal.", "normalVariance.",
                               "depthVariance.", "position.", "sampleCount.", "noisy."})
        if (startsWith(name, p)) return true;
    return name == "depth.Z";
}

/// The view-layer prefix of a Cycles file ("ViewLayer.", "" ...), or nothing if not Cycles.
std::optional<std::string> cyclesPrefix(const std::vector<std::string>& names) {
    for (std::string_view suffix :
         {"Combined.R", "Denoising Albedo.R", "Denoising Normal.X", "Denoising Depth.Z"})
        for (const std::string& n : names)
            if (endsWith(n, suffix)) {
                std::string prefix = n.substr(0, n.size() - suffix.size());
                if (prefix.empty() || prefix.back() == '.') return prefix;
            }
    return std::nullopt;
}

std::string joinNames(const std::vector<std::string>& names, std::size_t limit) {
    std::string out;
    for (std::size_t i = 0; i < names.size() && i < limit; ++i) out += (i ? ", " : "") + names[i];
    if (names.size() > limit) out += ", ...";
    return out;
}

}  // namespace

ChannelPlan planChannels(const std::vector<std::string>& names, bool hasGlintAttributes,
                         const std::string& file) {
    auto has = [&](const std::string& n) {
        return std::find(names.begin(), names.end(), n) != names.end();
    };
    auto hasPrefix = [&](std::string_view p) {
        return std::any_of(names.begin(), names.end(),
                           [&](const std::string& n) { return startsWith(n, p); });
    };

    // Choose the convention: Glint's attributes or Glint-only names win, then the most specific
    // foreign names; a file with just R,G,B reads as Glint's.
    ChannelPlan plan;
    std::vector<Candidate> candidates;
    const std::optional<std::string> prefix = cyclesPrefix(names);
    if (hasGlintAttributes || std::any_of(names.begin(), names.end(), isGlintOnly)) {
        plan = {"glint", {}, "world", "cameraZ", ""};
        candidates = glintCandidates();
    } else if (prefix) {
        // Cycles writes its denoising normal in camera space and its depth as ray length.
        plan = {"cycles", {}, "camera", "rayDistance", ""};
        candidates = cyclesCandidates(*prefix);
    } else if (hasPrefix("Albedo.") || hasPrefix("Ns.") || hasPrefix("N.") || hasPrefix("P.") ||
               hasPrefix("Variance.")) {
        // pbrt-v4's GBufferFilm writes geometry in camera space by default.
        plan = {"pbrt", {}, "camera", "cameraZ", "camera"};
        candidates = pbrtCandidates();
    } else if (hasPrefix("sh_normal.") || has("depth.T") || hasPrefix("albedo.")) {
        // Mitsuba's sh_normal is in world space and depth.T is the ray length t.
        plan = {"mitsuba", {}, "world", "rayDistance", ""};
        candidates = mitsubaCandidates();
    } else {
        plan = {"glint", {}, "world", "cameraZ", ""};
        candidates = glintCandidates();
    }

    // Take, for each layer, the first candidate whose channels are all present.
    std::array<bool, kLayerCount> done{};
    std::array<std::string, kLayerCount> partial;
    for (const Candidate& c : candidates) {
        if (done[int(c.layer)]) continue;
        std::vector<int> idx;
        std::vector<std::string> missing;
        for (const std::string& n : c.names) {
            auto it = std::find(names.begin(), names.end(), n);
            if (it == names.end())
                missing.push_back(n);
            else
                idx.push_back(int(it - names.begin()));
        }
        if (missing.empty()) {
            plan.layers.push_back({c.layer, std::move(idx), c.perSampleVariance});
            done[int(c.layer)] = true;
        } else if (!idx.empty() && partial[int(c.layer)].empty()) {
            partial[int(c.layer)] =
                joinNames(missing, 3) + " missing (expected " + joinNames(c.names, 3) + ")";
        }
    }

    if (!done[int(Layer::Color)]) {
        std::string expected = "R, G, B";
        if (plan.source == "cycles") expected = joinNames(cyclesCandidates(*prefix)[0].names, 3);
        throw Error(ErrorKind::Format,
                    "no colour channels: expected " + expected + " (file has " +
                        (names.empty() ? std::string("no channels") : joinNames(names, 12)) + ")",
                    file, "channels");
    }
    for (int l = 0; l < kLayerCount; ++l)
        if (!done[l] && !partial[l].empty())
            throw Error(
                ErrorKind::Format,
                "incomplete layer '" + std::string(layerDisplayName(Layer(l))) + "': " + partial[l],
                file, "channels");
    return plan;
}

}  // namespace glint::detail
