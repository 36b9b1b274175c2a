#include "glint/image/frame_buffers.h"

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
        default:
            return std::nullopt;
    }
}

FrameBuffers::FrameBuffers(int width, int height) : m_width(width), m_height(height) {
    m_layers[int(Layer::Color)] = Image(width, height, 3);
}

Image& FrameBuffers::layer(Layer l) {
    if (!has(l))
        throw Error(ErrorKind::InvalidArgument,
                    "frame has no '" + std::string(layerDisplayName(l)) + "' layer");
    return m_layers[int(l)];
}

const Image& FrameBuffers::layer(Layer l) const {
    return const_cast<FrameBuffers*>(this)->layer(l);
}

void FrameBuffers::set(Layer l, Image image) {
    const LayerInfo& info = layerInfo(l);
    if (image.width() != m_width || image.height() != m_height || image.channels() != info.channels)
        throw Error(ErrorKind::InvalidArgument,
                    "layer '" + std::string(layerDisplayName(l)) + "' must be " +
                        std::to_string(m_width) + "x" + std::to_string(m_height) + "x" +
                        std::to_string(info.channels) + ", got " + std::to_string(image.width()) +
                        "x" + std::to_string(image.height()) + "x" +
                        std::to_string(image.channels()));
    m_layers[int(l)] = std::move(image);
}

void FrameBuffers::remove(Layer l) {
    GLINT_CHECK(l != Layer::Color, "the colour layer cannot be removed");
    m_layers[int(l)] = Image();
}

Image& FrameBuffers::ensure(Layer l) {
    if (!has(l)) m_layers[int(l)] = Image(m_width, m_height, layerInfo(l).channels);
    return m_layers[int(l)];
}

}  // namespace glint
