#include "glint/image/frame_buffers.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "glint/image/error.h"

namespace glint {

namespace {
constexpr std::array<LayerInfo, kLayerCount> kLayers{{
    {Layer::Color, "", 3, {"R", "G", "B"}},
    {Layer::Variance, "variance", 3, {"R", "G", "B"}},
    {Layer::Albedo, "albedo", 3, {"R", "G", "B"}},
    {Layer::AlbedoVariance, "albedoVariance", 3, {"R", "G", "B"}},
    {Layer::Normal, "normal", 3, {"X", "Y", "Z"}},
    {Layer::NormalVariance, "normalVariance", 3, {"X", "Y", "Z"}},
    {Layer::Depth, "depth", 1, {"Z", "", ""}},
    {Layer::DepthVariance, "depthVariance", 1, {"Z", "", ""}},
    {Layer::Position, "position", 3, {"X", "Y", "Z"}},
    {Layer::SampleCount, "sampleCount", 1, {"Y", "", ""}},
    {Layer::Noisy, "noisy", 3, {"R", "G", "B"}},
    {Layer::HalfColor, "halfColor", 3, {"R", "G", "B"}},
    {Layer::HalfVariance, "halfVariance", 3, {"R", "G", "B"}},
    {Layer::HalfAlbedo, "halfAlbedo", 3, {"R", "G", "B"}},
    {Layer::HalfAlbedoVariance, "halfAlbedoVariance", 3, {"R", "G", "B"}},
    {Layer::HalfNormal, "halfNormal", 3, {"X", "Y", "Z"}},
    {Layer::HalfNormalVariance, "halfNormalVariance", 3, {"X", "Y", "Z"}},
    {Layer::HalfDepth, "halfDepth", 1, {"Z", "", ""}},
    {Layer::HalfDepthVariance, "halfDepthVariance", 1, {"Z", "", ""}},
    {Layer::HalfSampleCount, "halfSampleCount", 1, {"Y", "", ""}},
}};
}  // namespace

const LayerInfo& layerInfo(Layer layer) {
    return kLayers[int(layer)];
}

std::string_view layerDisplayName(Layer layer) {
    return layer == Layer::Color ? std::string_view("color") : layerInfo(layer).name;
}

std::optional<Layer> findLayer(std::string_view name) {
    if (name == "rgb") return Layer::Color;
    for (int l = 0; l < kLayerCount; ++l)
        if (layerDisplayName(Layer(l)) == name) return Layer(l);
    return std::nullopt;
}

std::string channelName(Layer layer, int c) {
    const LayerInfo& info = layerInfo(layer);
    GLINT_CHECK(c >= 0 && c < info.channels);
    if (info.name.empty()) return std::string(info.suffixes[c]);
    return std::string(info.name) + "." + std::string(info.suffixes[c]);
}

namespace {
// The layer of the file `frame` was read from that holds its `layer`.
Layer layerOfFile(const FrameBuffers& frame, Layer layer) {
    return layer == Layer::Color ? frame.metadata().colorReadFrom : layer;
}
}  // namespace

std::string layerInFile(const FrameBuffers& frame, Layer layer) {
    const Layer from = layerOfFile(frame, layer);
    if (from == Layer::Noisy) return "the noisy layer (the render the file keeps)";
    return "the " + std::string(layerDisplayName(from));
}

std::string channelInFile(const FrameBuffers& frame, Layer layer, int c) {
    return channelName(layerOfFile(frame, layer), c);
}

std::optional<Layer> varianceOf(Layer layer) {
    switch (layer) {
        case Layer::Variance:
            return Layer::Color;
        case Layer::AlbedoVariance:
            return Layer::Albedo;
        case Layer::NormalVariance:
            return Layer::Normal;
        case Layer::DepthVariance:
            return Layer::Depth;
        case Layer::HalfVariance:
            return Layer::HalfColor;
        case Layer::HalfAlbedoVariance:
            return Layer::HalfAlbedo;
        case Layer::HalfNormalVariance:
            return Layer::HalfNormal;
        case Layer::HalfDepthVariance:
            return Layer::HalfDepth;
        default:
            return std::nullopt;
    }
}

std::optional<Layer> varianceLayer(Layer layer) {
    switch (layer) {
        case Layer::Color:
            return Layer::Variance;
        case Layer::Albedo:
            return Layer::AlbedoVariance;
        case Layer::Normal:
            return Layer::NormalVariance;
        case Layer::Depth:
            return Layer::DepthVariance;
        case Layer::HalfColor:
            return Layer::HalfVariance;
        case Layer::HalfAlbedo:
            return Layer::HalfAlbedoVariance;
        case Layer::HalfNormal:
            return Layer::HalfNormalVariance;
        case Layer::HalfDepth:
            return Layer::HalfDepthVariance;
        default:
            return std::nullopt;
    }
}

FrameBuffers::FrameBuffers(int width, int height) : m_width(width), m_height(height) {
    m_layers[int(Layer::Color)] = std::make_shared<Image>(width, height, 3);
}

FrameBuffers::FrameBuffers(const FrameBuffers& other)
    : m_width(other.m_width), m_height(other.m_height), m_metadata(other.m_metadata) {
    for (int l = 0; l < kLayerCount; ++l)
        if (other.m_layers[l]) m_layers[l] = std::make_shared<Image>(*other.m_layers[l]);
}

FrameBuffers& FrameBuffers::operator=(const FrameBuffers& other) {
    if (this != &other) *this = FrameBuffers(other);
    return *this;
}

Image& FrameBuffers::owned(Layer l) {
    std::shared_ptr<Image>& held = m_layers[int(l)];
    if (held.use_count() > 1) held = std::make_shared<Image>(*held);
    return *held;
}

Image& FrameBuffers::layer(Layer l) {
    if (!has(l))
        throw Error(ErrorKind::InvalidArgument,
                    "frame has no '" + std::string(layerDisplayName(l)) + "' layer");
    return owned(l);
}

const Image& FrameBuffers::layer(Layer l) const {
    if (!has(l))
        throw Error(ErrorKind::InvalidArgument,
                    "frame has no '" + std::string(layerDisplayName(l)) + "' layer");
    return *m_layers[int(l)];
}

namespace {
// Throws unless `image` has the shape of layer `l` of a width × height frame.
void checkShape(Layer l, const Image& image, int width, int height) {
    const LayerInfo& info = layerInfo(l);
    if (image.width() != width || image.height() != height || image.channels() != info.channels)
        throw Error(ErrorKind::InvalidArgument,
                    "layer '" + std::string(layerDisplayName(l)) + "' must be " +
                        std::to_string(width) + "x" + std::to_string(height) + "x" +
                        std::to_string(info.channels) + ", got " + std::to_string(image.width()) +
                        "x" + std::to_string(image.height()) + "x" +
                        std::to_string(image.channels()));
}
}  // namespace

void FrameBuffers::set(Layer l, Image image) {
    checkShape(l, image, m_width, m_height);
    m_layers[int(l)] = std::make_shared<Image>(std::move(image));
    if (l == Layer::Color) m_metadata.colorReadFrom = Layer::Color;
}

void FrameBuffers::shareLayer(Layer l, const FrameBuffers& from, Layer fromLayer) {
    checkShape(l, from.layer(fromLayer), m_width, m_height);
    m_layers[int(l)] = from.m_layers[int(fromLayer)];
    if (l == Layer::Color) m_metadata.colorReadFrom = Layer::Color;
}

FrameBuffers FrameBuffers::sharedCopy() const {
    FrameBuffers out;
    out.m_width = m_width, out.m_height = m_height;
    out.m_layers = m_layers;
    out.m_metadata = m_metadata;
    return out;
}

void FrameBuffers::remove(Layer l) {
    GLINT_CHECK(l != Layer::Color, "the colour layer cannot be removed");
    m_layers[int(l)] = nullptr;
}

Image& FrameBuffers::ensure(Layer l) {
    if (!has(l))
        m_layers[int(l)] = std::make_shared<Image>(m_width, m_height, layerInfo(l).channels);
    return owned(l);
}

std::optional<Layer> halfLayer(Layer layer) {
    if (layer == Layer::Position || layer == Layer::Noisy || isHalfLayer(layer))
        return std::nullopt;
    // The half layers follow the mean layers' order, without position.
    const int offset = int(layer) < int(Layer::Position) ? int(layer) : int(layer) - 1;
    return Layer(int(Layer::HalfColor) + offset);
}

namespace {
std::string shortNumber(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(v));
    return text;
}
}  // namespace

void checkHalves(const FrameBuffers& frame, const std::string& file) {
    for (int l = 0; l < kLayerCount; ++l) {
        const std::optional<Layer> half = halfLayer(Layer(l));
        if (half && frame.has(Layer(l)) && !frame.has(*half))
            throw Error(ErrorKind::Format,
                        "has no " + std::string(layerDisplayName(*half)) +
                            " layer: the two halves need every half layer (render with "
                            "glint-render --set halfBuffers=true)",
                        file, "layer '" + std::string(layerDisplayName(*half)) + "'");
    }
    if (!frame.has(Layer::SampleCount))
        throw Error(ErrorKind::Format, "has no sampleCount layer: the halves need the counts", file,
                    "layer 'sampleCount'");
    const Image& n = frame.layer(Layer::SampleCount);
    const Image& nbImage = frame.layer(Layer::HalfSampleCount);
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x)
            if (!(nbImage(x, y, 0) >= 0.0f && nbImage(x, y, 0) <= n(x, y, 0)))
                throw Error(ErrorKind::InvalidArgument,
                            "halfSampleCount " + shortNumber(nbImage(x, y, 0)) +
                                " is not in [0, sampleCount = " + shortNumber(n(x, y, 0)) + "]",
                            file, "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ")");
}

std::pair<FrameBuffers, FrameBuffers> splitHalves(const FrameBuffers& frame,
                                                  const std::string& file) {
    checkHalves(frame, file);
    const int w = frame.width(), h = frame.height();
    // B is the half layers, A starts as the whole's; both shared, not copied.
    FrameBuffers a(w, h), b(w, h);
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        if (isHalfLayer(layer) || !frame.has(layer)) continue;
        const std::optional<Layer> half = halfLayer(layer);
        a.shareLayer(layer, frame, layer);
        b.shareLayer(layer, frame, half ? *half : layer);
    }
    const Image& n = frame.layer(Layer::SampleCount);
    const Image& nbImage = frame.layer(Layer::HalfSampleCount);
    // A = whole − B, per mean layer with its variance of the mean, into layers of its own.
    for (Layer mean : {Layer::Color, Layer::Albedo, Layer::Normal, Layer::Depth}) {
        if (!frame.has(mean)) continue;
        const Layer halfMean = *halfLayer(mean);
        const std::optional<Layer> var = varianceLayer(mean);
        const bool withVariance = frame.has(*var);
        const Image& m = frame.layer(mean);
        const Image& mb = frame.layer(halfMean);
        Image ma(w, h, m.channels()), va;
        const Image* v = withVariance ? &frame.layer(*var) : nullptr;
        const Image* vb = withVariance ? &frame.layer(*halfLayer(*var)) : nullptr;
        if (withVariance) va = Image(w, h, m.channels());
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const double nt = n(x, y, 0), nb = nbImage(x, y, 0), na = nt - nb;
                for (int c = 0; c < m.channels(); ++c) {
                    const double meanA =
                        na > 0.0 ? (nt * double(m(x, y, c)) - nb * double(mb(x, y, c))) / na : 0.0;
                    ma(x, y, c) = float(meanA);
                    if (!withVariance) continue;
                    const double m2 = double((*v)(x, y, c)) * nt * (nt - 1.0);
                    const double m2b = double((*vb)(x, y, c)) * nb * std::max(nb - 1.0, 0.0);
                    const double delta = double(mb(x, y, c)) - meanA;
                    const double m2a =
                        nt > 0.0 ? std::max(0.0, m2 - m2b - delta * delta * na * nb / nt) : 0.0;
                    va(x, y, c) = na > 1.0 ? float(m2a / (na * (na - 1.0))) : 0.0f;
                }
            }
        a.set(mean, std::move(ma));
        if (withVariance) a.set(*var, std::move(va));
    }
    Image countA(w, h, 1);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) countA(x, y, 0) = n(x, y, 0) - nbImage(x, y, 0);
    a.set(Layer::SampleCount, std::move(countA));
    a.metadata() = frame.metadata();
    b.metadata() = frame.metadata();
    b.metadata().colorReadFrom = Layer::HalfColor;  // errors about B's colour name halfColor
    a.metadata().spp = frame.metadata().spp - frame.metadata().spp / 2;
    b.metadata().spp = frame.metadata().spp / 2;
    a.metadata().extra.erase("halfBuffers");
    b.metadata().extra.erase("halfBuffers");
    return {std::move(a), std::move(b)};
}

}  // namespace glint
