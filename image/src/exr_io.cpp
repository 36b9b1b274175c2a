// Layered EXR and plain image I/O through OpenImageIO (docs/image.md, "The layered EXR").
#include <unistd.h>

#include <OpenImageIO/imageio.h>
#include <OpenImageIO/strutil.h>
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

#include "channel_aliases.h"
#include "exr_layout.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "oiio_helpers.h"

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
std::optional<T> intAttribute(const OIIO::ImageSpec& spec, const std::string& name,
                              const std::string& file) {
    const OIIO::ParamValue* p = spec.find_attribute(name);
    if (!p) return std::nullopt;
    if (p->type() == OIIO::TypeInt) return T(p->get_int());
    if (p->type() == OIIO::TypeString) {
        if (auto v = parseNumber<T>(p->get_string())) return v;
    }
    throw Error(ErrorKind::Format, "expected an integer, got '" + p->get_string() + "'", file,
                "attribute " + name);
}

/// FrameMetadata from glint:* attributes, with `plan` giving the defaults of foreign files.
FrameMetadata readMetadata(const OIIO::ImageSpec& spec, const detail::ChannelPlan& plan,
                           const std::string& file) {
    FrameMetadata md;
    md.source = plan.source;
    md.normalSpace = plan.normalSpace;
    md.depthKind = plan.depthKind;
    if (!plan.positionSpace.empty()) md.extra["positionSpace"] = plan.positionSpace;

    for (const OIIO::ParamValue& p : spec.extra_attribs) {
        const std::string name = p.name().string();
        if (name.rfind(kPrefix, 0) != 0) continue;
        const std::string key = name.substr(kPrefix.size());
        const std::string value = p.get_string(1 << 20);
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
    md.spp = intAttribute<int>(spec, "glint:spp", file).value_or(0);
    md.seed = intAttribute<std::uint64_t>(spec, "glint:seed", file).value_or(0);
    md.nonFiniteSamples =
        intAttribute<std::int64_t>(spec, "glint:nonFiniteSamples", file).value_or(0);

    // Sample counts of other renderers: pbrt-v4 writes samplesPerPixel, Blender stamps
    // cycles.<view layer>.samples.
    if (md.spp == 0) {
        if (auto spp = intAttribute<int>(spec, "samplesPerPixel", file)) md.spp = *spp;
    }
    if (md.spp == 0 && plan.source == "cycles") {
        for (const OIIO::ParamValue& p : spec.extra_attribs) {
            const std::string name = p.name().string();
            if (name.rfind("cycles.", 0) == 0 && name.size() > 8 &&
                name.substr(name.size() - 8) == ".samples")
                md.spp = intAttribute<int>(spec, name, file).value_or(0);
        }
    }
    return md;
}

/// Selects OpenImageIO's OpenEXRCore-based reader, which reads many-channel files 2-3x faster
/// than the classic one (docs/image.md). This is a process-wide OpenImageIO option; it is set
/// once, on first use, and never changed afterwards.
void useFastExrReader() {
    static const bool set = OIIO::attribute("openexr:core", 1);
    (void)set;
}

}  // namespace

FrameBuffers readExr(const std::filesystem::path& path) {
    const std::string file = path.string();
    useFastExrReader();
    auto in = detail::openImage(path);
    const std::string format = in->format_name();
    if (format != "openexr")
        throw Error(ErrorKind::Format, "expected an OpenEXR file, got a " + format + " file", file,
                    "open");
    const detail::ExrLayout layout = detail::readExrLayout(*in, file);
    const OIIO::ImageSpec& spec = layout.spec;
    if (spec.width <= 0 || spec.height <= 0 || spec.depth != 1)
        throw Error(ErrorKind::Format, "expected a 2D image with pixels", file, "header");
    checkPlausibleSize(spec.width, spec.height, layout.channels(), path);

    bool hasGlintAttributes = false;
    for (const OIIO::ParamValue& p : spec.extra_attribs)
        hasGlintAttributes |= p.name().string().rfind(kPrefix, 0) == 0;
    const detail::ChannelPlan plan =
        detail::planChannels(layout.channelNames, hasGlintAttributes, file);
    FrameMetadata metadata = readMetadata(spec, plan, file);

    // Destination layers, with where each of their channels lies in the file.
    const int w = spec.width, h = spec.height, n = layout.channels();
    FrameBuffers frame(w, h);
    struct Target {
        float* data;
        int channels;
        const int* fileChannels;
        float divisor;
    };
    std::vector<Target> targets;
    for (const detail::LayerSource& src : plan.layers) {
        float divisor = 1.0f;
        if (src.perSampleVariance) {
            // pbrt-v4's Variance is that of one sample; the variance of the mean is it / spp.
            if (metadata.spp <= 0)
                throw Error(ErrorKind::Format,
                            "Variance.R/G/B is per-sample (pbrt-v4) and must be divided by the "
                            "sample count, but the file has no samplesPerPixel attribute",
                            file, "attribute samplesPerPixel");
            divisor = float(metadata.spp);
        }
        Image& layer = frame.ensure(src.layer);
        targets.push_back({layer.data().data(), layer.channels(), src.channels.data(), divisor});
    }

    // Read strips of all channels as float32 (bit-exact for float files) and scatter them into
    // the layers, pixel by pixel so that every buffer is walked once in order.
    const int stripRows = layout.stripRows();
    std::vector<float> strip(std::size_t(std::min(stripRows, h)) * w * n);
    for (int y0 = 0; y0 < h; y0 += stripRows) {
        const int y1 = std::min(h, y0 + stripRows);
        detail::readExrRows(*in, layout, y0, y1, strip.data(), file);
        tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& r) {
            for (int y = r.begin(); y != r.end(); ++y) {
                const float* src = strip.data() + std::size_t(y - y0) * w * n;
                const std::size_t first = std::size_t(y) * w;
                for (int x = 0; x < w; ++x, src += n)
                    for (const Target& t : targets) {
                        float* dst = t.data + (first + x) * t.channels;
                        for (int c = 0; c < t.channels; ++c)
                            dst[c] = src[t.fileChannels[c]] / t.divisor;
                    }
            }
        });
    }
    in->close();
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

    // Channel list: every present layer in Layer order, with the names of docs/image.md.
    std::vector<const Image*> layers;
    std::vector<std::string> names;
    for (int l = 0; l < kLayerCount; ++l) {
        const Image* im = frame.find(Layer(l));
        if (!im) continue;
        layers.push_back(im);
        for (int c = 0; c < im->channels(); ++c) names.push_back(channelName(Layer(l), c));
    }
    const int w = frame.width(), h = frame.height(), n = int(names.size());

    OIIO::ImageSpec spec(w, h, n, OIIO::TypeFloat);
    spec.channelnames = names;
    spec.alpha_channel = -1;
    spec.z_channel = -1;
    spec.attribute("compression", options.compression == ExrCompression::Zip ? "zip" : "none");
    spec.attribute("glint:spp", md.spp);
    spec.attribute("glint:seed", std::to_string(md.seed));
    spec.attribute("glint:integrator", md.integrator);
    spec.attribute("glint:varianceOf", md.varianceOf);
    spec.attribute("glint:normalSpace", md.normalSpace);
    spec.attribute("glint:depth", md.depthKind);
    spec.attribute("glint:scene", md.scene);
    spec.attribute("glint:nonFiniteSamples", std::to_string(md.nonFiniteSamples));
    for (const auto& [key, value] : md.extra) spec.attribute(std::string(kPrefix) + key, value);

    // Interleave the layers into the file's channel order, strip by strip, pixel by pixel.
    constexpr int kStripRows = 32;
    auto fill = [&](int y0, int y1, float* strip) {
        tbb::parallel_for(tbb::blocked_range<int>(y0, y1), [&](const tbb::blocked_range<int>& r) {
            for (int y = r.begin(); y != r.end(); ++y) {
                float* dst = strip + std::size_t(y - y0) * w * n;
                for (int x = 0; x < w; ++x)
                    for (const Image* im : layers) {
                        const float* src = im->row(y) + std::size_t(x) * im->channels();
                        dst = std::copy_n(src, im->channels(), dst);
                    }
            }
        });
    };
    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        detail::writeOiioStrips(tmp, path, spec, kStripRows, fill);
    });
}

Image readImage(const std::filesystem::path& path, bool linearize) {
    const std::string file = path.string();
    useFastExrReader();
    auto in = detail::openImage(path);
    const OIIO::ImageSpec spec = in->spec();
    if (spec.deep || spec.width <= 0 || spec.height <= 0 || spec.depth != 1 || spec.nchannels <= 0)
        throw Error(ErrorKind::Format, "expected a flat 2D image with pixels", file, "header");
    checkPlausibleSize(spec.width, spec.height, spec.nchannels, path);
    Image image(spec.width, spec.height, spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeFloat, image.data().data()))
        throw Error(ErrorKind::Format,
                    "truncated or corrupt pixel data (" + detail::firstLine(in->geterror()) + ")",
                    file, "pixels");
    in->close();

    const bool srgb = srgbEncodedFile(spec.get_string_attribute("oiio:ColorSpace"),
                                      spec.format == OIIO::TypeDesc::UINT8);
    if (linearize && srgb) {
        // Decode every colour channel; alpha stays linear.
        float* data = image.data().data();
        for (std::size_t i = 0; i < image.pixelCount(); ++i)
            for (int c = 0; c < spec.nchannels; ++c)
                if (c != spec.alpha_channel)
                    data[i * spec.nchannels + c] = srgbDecode(data[i * spec.nchannels + c]);
    }
    return image;
}

void writeImage(const Image& image, const std::filesystem::path& path) {
    const std::string file = path.string();
    if (image.empty())
        throw Error(ErrorKind::InvalidArgument, "cannot write an empty image", file, "write");
    const int n = image.channels();
    const bool exr = detail::lowerExtension(path) == ".exr";
    OIIO::ImageSpec spec(image.width(), image.height(), n, exr ? OIIO::TypeFloat : OIIO::TypeUInt8);
    if (n == 1) spec.channelnames = {"Y"};
    if (n == 2) spec.channelnames = {"Y", "A"};
    spec.alpha_channel = (n == 2 || n == 4) ? n - 1 : -1;

    if (exr) {
        writeAtomically(path, [&](const std::filesystem::path& tmp) {
            detail::writeOiio(tmp, path, spec, OIIO::TypeFloat, image.data().data());
        });
        return;
    }
    // 8-bit: sRGB-encode colour channels so that readImage(path, true) returns linear values.
    std::vector<unsigned char> bytes(image.data().size());
    const float* src = image.data().data();
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        float v = src[i];
        if (int(i % n) != spec.alpha_channel) v = srgbEncode(v);
        v = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
        bytes[i] = static_cast<unsigned char>(std::lround(v * 255.0f));
    }
    spec.attribute("oiio:ColorSpace", "sRGB");
    writeAtomically(path, [&](const std::filesystem::path& tmp) {
        detail::writeOiio(tmp, path, spec, OIIO::TypeUInt8, bytes.data());
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
