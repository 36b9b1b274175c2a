// Images built from tev packets (glint/image/tev_images.h).
#include "glint/image/tev_images.h"

#include <algorithm>

#include "channel_aliases.h"
#include "glint/image/error.h"
#include "glint/image/memory.h"

namespace glint::tev {

namespace {

std::string imageLabel(const std::string& name) {
    return "tev image '" + name + "'";
}

/// Each of `wanted` as an index into `channels`; throws naming the first one missing.
std::vector<int> channelIndices(const std::vector<std::string>& wanted,
                                const std::vector<std::string>& channels, const std::string& name) {
    std::vector<int> out;
    for (const std::string& c : wanted) {
        const auto it = std::find(channels.begin(), channels.end(), c);
        if (it == channels.end())
            throw Error(
                ErrorKind::InvalidArgument,
                "the update names channel '" + c + "', which the image was not created with",
                imageLabel(name), "channels");
        const int index = int(it - channels.begin());
        if (std::find(out.begin(), out.end(), index) != out.end())
            throw Error(ErrorKind::InvalidArgument, "the update names channel '" + c + "' twice",
                        imageLabel(name), "channels");
        out.push_back(index);
    }
    return out;
}

}  // namespace

Change ReceivedImages::apply(const Packet& packet, std::uint64_t memoryLimit) {
    if (const auto* p = std::get_if<CreateImage>(&packet)) {
        std::vector<std::string> sorted = p->channels;
        std::sort(sorted.begin(), sorted.end());
        if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end());
            twice != sorted.end())
            throw Error(ErrorKind::InvalidArgument, "channel '" + *twice + "' is named twice",
                        imageLabel(p->name), "channels");
        // The sizes are the protocol's (decode checked them); the memory is this machine's.
        const std::uint64_t bytes =
            saturatingMul(saturatingMul(std::uint64_t(p->width), std::uint64_t(p->height)),
                          saturatingMul(p->channels.size(), sizeof(float)));
        checkMemory(bytes, memoryLimit,
                    "a " + std::to_string(p->width) + "x" + std::to_string(p->height) + "x" +
                        std::to_string(p->channels.size()) + " image",
                    imageLabel(p->name), "create");
        // A second CreateImage of a name starts it again (as tev does).
        m_images[p->name] = {p->channels, Image(p->width, p->height, int(p->channels.size())),
                             false};
        return {Change::Created, p->name};
    }
    if (const auto* p = std::get_if<UpdateImage>(&packet)) {
        const auto it = m_images.find(p->name);
        if (it == m_images.end())
            throw Error(ErrorKind::InvalidArgument, "no image of this name was created",
                        imageLabel(p->name), "update");
        Image& image = it->second.pixels;
        if (p->x < 0 || p->y < 0 || p->width > image.width() - p->x ||
            p->height > image.height() - p->y)
            throw Error(ErrorKind::InvalidArgument,
                        "the tile at (" + std::to_string(p->x) + ", " + std::to_string(p->y) +
                            ") of " + std::to_string(p->width) + "x" + std::to_string(p->height) +
                            " lies outside the " + std::to_string(image.width()) + "x" +
                            std::to_string(image.height()) + " image",
                        imageLabel(p->name), "update");
        // Only now, inside the image, can the tile's far corner not overflow.
        const Rect tile{p->x, p->x + p->width, p->y, p->y + p->height};
        const std::vector<int> target = channelIndices(p->channels, it->second.channels, p->name);
        const std::size_t n = target.size();
        for (int y = tile.y0; y < tile.y1; ++y) {
            const float* src = p->pixels.data() + std::size_t(y - tile.y0) * p->width * n;
            for (int x = tile.x0; x < tile.x1; ++x, src += n)
                for (std::size_t c = 0; c < n; ++c) image(x, y, target[c]) = src[c];
        }
        return {Change::Updated, p->name};
    }
    if (const auto* p = std::get_if<CloseImage>(&packet)) {
        const auto it = m_images.find(p->name);
        if (it == m_images.end())
            throw Error(ErrorKind::InvalidArgument, "no image of this name was created",
                        imageLabel(p->name), "close");
        it->second.complete = true;
        return {Change::Closed, p->name};
    }
    return {};
}

const ReceivedImages::Received& ReceivedImages::find(const std::string& name) const {
    const auto it = m_images.find(name);
    if (it == m_images.end())
        throw Error(ErrorKind::InvalidArgument, "no image of this name", imageLabel(name));
    return it->second;
}

bool ReceivedImages::complete(const std::string& name) const {
    const auto it = m_images.find(name);
    return it != m_images.end() && it->second.complete;
}

FrameBuffers ReceivedImages::frame(const std::string& name) const {
    const Received& r = find(name);
    const Image& pixels = r.pixels;
    const int n = pixels.channels();
    std::vector<detail::LayerSource> layers;
    FrameMetadata metadata;
    try {
        const detail::ChannelPlan plan = detail::planChannels(r.channels, false, imageLabel(name));
        layers = plan.layers;
        metadata.source = plan.source;
        metadata.normalSpace = plan.normalSpace;
        metadata.depthKind = plan.depthKind;
        if (!plan.positionSpace.empty()) metadata.extra["positionSpace"] = plan.positionSpace;
    } catch (const Error&) {
        // No R,G,B (or an incomplete layer): the first channels are the colour.
        layers = {{Layer::Color, {0, std::min(1, n - 1), std::min(2, n - 1)}}};
        metadata.source = "tev";
    }
    std::erase_if(layers, [](const detail::LayerSource& s) { return s.perSampleVariance; });
    FrameBuffers frame(pixels.width(), pixels.height());
    for (const detail::LayerSource& src : layers) {
        Image& layer = frame.ensure(src.layer);
        const int lc = layer.channels();
        for (int y = 0; y < pixels.height(); ++y) {
            const float* in = pixels.row(y);
            float* out = layer.row(y);
            for (int x = 0; x < pixels.width(); ++x, in += n, out += lc)
                for (int c = 0; c < lc; ++c) out[c] = in[src.channels[std::size_t(c)]];
        }
    }
    metadata.scene = name;
    frame.metadata() = std::move(metadata);
    return frame;
}

}  // namespace glint::tev
