// Layered EXR and plain image I/O: EXRs through OpenEXR, other formats through the module of
// other_formats.h (docs/image.md, "The layered EXR").
#include <unistd.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string_view>
#include <system_error>
#include <thread>

#include "channel_aliases.h"
#include "exr_layout.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "image_files.h"
#include "other_formats.h"

namespace glint {

namespace {

constexpr std::string_view kPrefix = "glint:";

/// A corrupt header can claim any size: refuse one that could not be a render (more than
/// 65536 pixels on a side or 2^28 pixels in all) before allocating anything for it.
void checkPlausibleSize(int width, int height, int channels, const std::filesystem::path& path) {
    const std::string file = path.string();
    constexpr long long kMaxSide = 1 << 16, kMaxPixels = 1LL << 28, kMaxChannels = 1024;
    if (width > kMaxSide || height > kMaxSide || (long long)width * height > kMaxPixels)
        throw Error(ErrorKind::Format,
                    "header claims " + std::to_string(width) + "x" + std::to_string(height) +
                        " pixels; expected at most 65536 per side and 2^28 in all",
                    file, "header");
    if (channels > kMaxChannels)
        throw Error(ErrorKind::Format,
                    "header claims " + std::to_string(channels) + " channels; expected at most " +
                        std::to_string(kMaxChannels),
                    file, "header");
    // No image format Glint reads compresses better than about 1000:1 (deflate's limit is
    // 1032:1), so a file claiming far more pixels than it can hold is refused before gigabytes
    // are allocated for it.
    std::error_code ec;
    const auto bytes = (long long)std::filesystem::file_size(path, ec);
    const long long samples = (long long)width * height * channels;
    if (!ec && samples / 2048 > bytes)
        throw Error(ErrorKind::Format,
                    "header claims " + std::to_string(width) + "x" + std::to_string(height) + "x" +
                        std::to_string(channels) + " samples, more than a file of " +
                        std::to_string(bytes) + " bytes can hold",
                    file, "header");
}
/// glint:* keys with a FrameMetadata field of their own; other glint:* keys go to `extra`.
constexpr std::array<std::string_view, 8> kKnownKeys{
    "spp", "seed", "integrator", "scene", "varianceOf", "normalSpace", "depth", "nonFiniteSamples"};

bool isKnownKey(std::string_view key) {
    return std::find(kKnownKeys.begin(), kKnownKeys.end(), key) != kKnownKeys.end();
}

/// Parses a whole decimal string as T; nullopt when it is not one.
template <typename T>
std::optional<T> parseNumber(std::string_view text) {
    T value{};
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

/// An integer attribute stored either as an EXR int or as a decimal string.
template <typename T>
std::optional<T> intAttribute(const detail::ExrLayout& layout, const std::string& name,
                              const std::string& file) {
    const detail::ExrAttribute* a = layout.find(name);
    if (!a) return std::nullopt;
    if (a->integer) return T(*a->integer);
    if (auto v = parseNumber<T>(a->text)) return v;
    throw Error(ErrorKind::Format, "expected an integer, got '" + a->text + "'", file,
                "attribute " + name);
}

/// FrameMetadata from glint:* attributes, with `plan` giving the defaults of foreign files.
FrameMetadata readMetadata(const detail::ExrLayout& layout, const detail::ChannelPlan& plan,
                           const std::string& file) {
    FrameMetadata md;
    md.source = plan.source;
    md.normalSpace = plan.normalSpace;
    md.depthKind = plan.depthKind;
    if (!plan.positionSpace.empty()) md.extra["positionSpace"] = plan.positionSpace;

    for (const detail::ExrAttribute& a : layout.attributes) {
        const std::string& name = a.name;
        if (name.rfind(kPrefix, 0) != 0) continue;
        const std::string key = name.substr(kPrefix.size());
        const std::string& value = a.text;
        if (key == "integrator")
            md.integrator = value;
        else if (key == "scene")
            md.scene = value;
        else if (key == "varianceOf")
            md.varianceOf = value;
        else if (key == "normalSpace")
            md.normalSpace = value;
        else if (key == "depth")
            md.depthKind = value;
        else if (!isKnownKey(key))
            md.extra[key] = value;
    }
    md.spp = intAttribute<int>(layout, "glint:spp", file).value_or(0);
    md.seed = intAttribute<std::uint64_t>(layout, "glint:seed", file).value_or(0);
    md.nonFiniteSamples =
        intAttribute<std::int64_t>(layout, "glint:nonFiniteSamples", file).value_or(0);

    // Sample counts of other renderers: pbrt-v4 writes samplesPerPixel, Blender stamps
    // cycles.<view layer>.samples.
    if (md.spp == 0) {
        if (auto spp = intAttribute<int>(layout, "samplesPerPixel", file)) md.spp = *spp;
    }
    if (md.spp == 0 && plan.source == "cycles") {
        for (const detail::ExrAttribute& a : layout.attributes) {
            const std::string& name = a.name;
            if (name.rfind("cycles.", 0) == 0 && name.size() > 8 &&
                name.substr(name.size() - 8) == ".samples")
                md.spp = intAttribute<int>(layout, name, file).value_or(0);
        }
    }
    return md;
}

/// The names OpenImageIO gives the channels of a plain image it writes (the names readImage's
/// earlier files have): Y; Y, A; R, G, B; R, G, B, A; then channel4, channel5, …
std::vector<std::string> plainChannelNames(int n) {
    if (n == 1) return {"Y"};
    if (n == 2) return {"Y", "A"};
    std::vector<std::string> names;
    for (int c = 0; c < n; ++c)
        names.push_back(c < 4 ? std::string(1, "RGBA"[c]) : "channel" + std::to_string(c));
    return names;
}

/// OpenEXR's own threads on (set once by the first EXR written): its line buffers are compressed
/// on as many threads as the machine has.
void useExrThreads() {
    static const bool set = [] {
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
        return true;
    }();
    (void)set;
}

/// Where a channel's values are: its first value, the strides between pixels and rows in bytes.
struct ChannelSource {
    const float* first;
    std::size_t xStride, yStride;
};

/// Writes one-part float EXR rows [0, height) of `names`, each channel c read from `channels[c]`,
/// with the attributes of `header`.
void writeFloatExr(const std::filesystem::path& tmp, const std::string& file, int width, int height,
                   const std::vector<std::string>& names,
                   const std::vector<ChannelSource>& channels, Imf::Header header) {
    useExrThreads();
    for (const std::string& name : names) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    Imf::FrameBuffer buffer;
    for (std::size_t c = 0; c < names.size(); ++c)
        buffer.insert(names[c],
                      Imf::Slice::Make(Imf::FLOAT, channels[c].first, Imath::V2i(0, 0), width,
                                       height, channels[c].xStride, channels[c].yStride));
    try {
        Imf::OutputFile out(tmp.c_str(), header);
        out.setFrameBuffer(buffer);
        out.writePixels(height);
    } catch (const std::exception& e) {
        throw Error(ErrorKind::Io, "cannot write the file (" + detail::firstLine(e.what()) + ")",
                    file, "write");
    }
}

}  // namespace

FrameBuffers readExr(const std::filesystem::path& path) {
    const std::string file = path.string();
    detail::ExrInput in(path);
    const detail::ExrLayout& layout = in.layout();
    if (layout.width <= 0 || layout.height <= 0)
        throw Error(ErrorKind::Format, "expected a 2D image with pixels", file, "header");
    checkPlausibleSize(layout.width, layout.height, layout.channels(), path);

    bool hasGlintAttributes = false;
    for (const detail::ExrAttribute& a : layout.attributes)
        hasGlintAttributes |= a.name.rfind(kPrefix, 0) == 0;
    const detail::ChannelPlan plan =
        detail::planChannels(layout.channelNames, hasGlintAttributes, file);
    FrameMetadata metadata = readMetadata(layout, plan, file);

    // Every layer channel is read straight from its file channel into the layer (bit for bit);
    // a file channel that feeds two layers (pbrt's P.Z: position and depth) is read into the
    // first and copied into the other.
    const int w = layout.width, h = layout.height;
    FrameBuffers frame(w, h);
    std::vector<detail::ExrTarget> targets;
    std::vector<std::pair<detail::ExrTarget, detail::ExrTarget>> copies;
    std::vector<std::pair<Image*, float>> divided;
    for (const detail::LayerSource& src : plan.layers) {
        Image& layer = frame.ensure(src.layer);
        const std::size_t xStride = sizeof(float) * std::size_t(layer.channels());
        for (int c = 0; c < layer.channels(); ++c) {
            const detail::ExrTarget t{src.channels[std::size_t(c)], layer.data().data() + c,
                                      xStride, xStride * std::size_t(w)};
            const auto earlier = std::find_if(targets.begin(), targets.end(), [&](const auto& e) {
                return e.channel == t.channel;
            });
            if (earlier == targets.end())
                targets.push_back(t);
            else
                copies.emplace_back(*earlier, t);
        }
        if (src.perSampleVariance) {
            // pbrt-v4's Variance is that of one sample; the variance of the mean is it / spp.
            if (metadata.spp <= 0)
                throw Error(ErrorKind::Format,
                            "Variance.R/G/B is per-sample (pbrt-v4) and must be divided by the "
                            "sample count, but the file has no samplesPerPixel attribute",
                            file, "attribute samplesPerPixel");
            divided.emplace_back(&layer, float(metadata.spp));
        }
    }
    in.read(targets);
    for (const auto& copy : copies)
        // Named, not a structured binding: clang 14 (make fuzz) cannot capture one.
        tbb::parallel_for(0, h, [&, &from = copy.first, &to = copy.second](int y) {
            for (int x = 0; x < w; ++x)
                *reinterpret_cast<float*>(reinterpret_cast<char*>(to.first) + y * to.yStride +
                                          x * to.xStride) =
                    *reinterpret_cast<const float*>(reinterpret_cast<const char*>(from.first) +
                                                    y * from.yStride + x * from.xStride);
        });
    for (const auto& [layer, divisor] : divided)
        for (float& v : layer->data()) v /= divisor;
    frame.metadata() = std::move(metadata);
    return frame;
}

void writeExr(const FrameBuffers& frame, const std::filesystem::path& path,
              const ExrWriteOptions& options) {
    const std::string file = path.string();
    if (frame.width() <= 0 || frame.height() <= 0 || !frame.has(Layer::Color))
        throw Error(ErrorKind::InvalidArgument, "cannot write an empty frame", file, "write");
    const FrameMetadata& md = frame.metadata();
    for (const auto& [key, value] : md.extra)
        if (key.empty() || isKnownKey(key))
            throw Error(ErrorKind::InvalidArgument,
                        "metadata extra key '" + key + "' is empty or shadows a glint:* field",
                        file, "metadata");

    // Channel list: every present layer in Layer order, with the names of docs/image.md, each
    // channel read straight from its layer.
    const int w = frame.width(), h = frame.height();
    std::vector<std::string> names;
    std::vector<ChannelSource> sources;
    for (int l = 0; l < kLayerCount; ++l) {
        const Image* im = frame.find(Layer(l));
        if (!im) continue;
        const std::size_t xStride = sizeof(float) * std::size_t(im->channels());
        for (int c = 0; c < im->channels(); ++c) {
            names.push_back(channelName(Layer(l), c));
            sources.push_back({im->row(0) + c, xStride, xStride * std::size_t(w)});
        }
    }

    Imf::Header header(w, h);
    header.compression() =
        options.compression == ExrCompression::Zip ? Imf::ZIP_COMPRESSION : Imf::NO_COMPRESSION;
    const auto text = [&](const std::string& name, const std::string& value) {
        header.insert(name, Imf::StringAttribute(value));
    };
    header.insert("glint:spp", Imf::IntAttribute(md.spp));
    text("glint:seed", std::to_string(md.seed));
    text("glint:integrator", md.integrator);
    text("glint:varianceOf", md.varianceOf);
    text("glint:normalSpace", md.normalSpace);
    text("glint:depth", md.depthKind);
    text("glint:scene", md.scene);
    text("glint:nonFiniteSamples", std::to_string(md.nonFiniteSamples));
    for (const auto& [key, value] : md.extra) text(std::string(kPrefix) + key, value);

    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        writeFloatExr(tmp, file, w, h, names, sources, header);
    });
}

Image readImage(const std::filesystem::path& path, bool linearize) {
    const std::string file = path.string();
    detail::checkRegularFile(path);
    if (!detail::isExr(path)) {
        // A PNG or JPEG is checked by its reader on the bytes it decodes.
        return detail::readOtherFormat(file, {}, detail::lowerExtension(path), linearize,
                                       [&](int width, int height, int channels) {
                                           checkPlausibleSize(width, height, channels, path);
                                       });
    }
    // An EXR: its first part's channels, in the order image tools show them; linear values.
    detail::ExrInput in(path);
    const detail::ExrLayout& layout = in.layout();
    const int n = layout.parts.front().channels;
    if (layout.width <= 0 || layout.height <= 0)
        throw Error(ErrorKind::Format, "expected a flat 2D image with pixels", file, "header");
    checkPlausibleSize(layout.width, layout.height, n, path);
    Image image(layout.width, layout.height, n);
    std::vector<detail::ExrTarget> targets;
    const std::size_t xStride = sizeof(float) * std::size_t(n);
    for (int c = 0; c < n; ++c)
        targets.push_back(
            {c, image.data().data() + c, xStride, xStride * std::size_t(layout.width)});
    in.read(targets);
    return image;
}

void writeImage(const Image& image, const std::filesystem::path& path) {
    const std::string file = path.string();
    if (image.empty())
        throw Error(ErrorKind::InvalidArgument, "cannot write an empty image", file, "write");
    const int n = image.channels();
    const std::vector<std::string> names = plainChannelNames(n);
    if (detail::lowerExtension(path) == ".exr") {
        std::vector<ChannelSource> sources;
        const std::size_t xStride = sizeof(float) * std::size_t(n);
        for (int c = 0; c < n; ++c)
            sources.push_back({image.data().data() + c, xStride, xStride * image.width()});
        Imf::Header header(image.width(), image.height());
        header.compression() = Imf::ZIP_COMPRESSION;
        writeAtomically(path, [&](const std::filesystem::path& tmp) {
            writeFloatExr(tmp, file, image.width(), image.height(), names, sources, header);
        });
        return;
    }
    // 8-bit: sRGB-encode colour channels so that readImage(path, true) returns linear values.
    const int alpha = (n == 2 || n == 4) ? n - 1 : -1;
    std::vector<unsigned char> bytes(image.data().size());
    const float* src = image.data().data();
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        float v = src[i];
        if (int(i % n) != alpha) v = srgbEncode(v);
        v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
        bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
    }
    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        detail::writeOtherFormat8(tmp, path, image.width(), image.height(), names, alpha, "sRGB",
                                  bytes.data());
    });
}

std::filesystem::path temporaryPathFor(const std::filesystem::path& path) {
    // A hidden sibling that keeps the extension (writers pick the format from it).
    return path.parent_path() / ("." + path.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                                 path.extension().string());
}

void writeAtomically(const std::filesystem::path& path,
                     const std::function<void(const std::filesystem::path&)>& write) {
    const std::filesystem::path tmp = temporaryPathFor(path);

    std::error_code ignored;
    try {
        write(tmp);
        std::error_code ec;
        std::filesystem::rename(tmp, path, ec);
        if (ec)
            throw Error(ErrorKind::Io,
                        "cannot move the finished file into place (" + ec.message() + ")",
                        path.string(), "rename");
    } catch (...) {
        std::filesystem::remove(tmp, ignored);
        throw;
    }
}

}  // namespace glint
