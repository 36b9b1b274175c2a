// Frames sent to tev as a created image and tiles of updates (glint/image/tev_client.h).
#include <algorithm>

#include "glint/image/tev_client.h"

namespace glint::tev {

namespace {

/// The layers sent: every present one but the half buffers.
std::vector<Layer> displayLayers(const FrameBuffers& frame) {
    std::vector<Layer> out;
    for (int l = 0; l < kLayerCount; ++l)
        if (frame.has(Layer(l)) && !isHalfLayer(Layer(l))) out.push_back(Layer(l));
    return out;
}

}  // namespace

std::vector<std::string> displayChannels(const FrameBuffers& frame) {
    std::vector<std::string> out;
    for (Layer l : displayLayers(frame))
        for (int c = 0; c < layerInfo(l).channels; ++c) out.push_back(channelName(l, c));
    return out;
}

CreateImage createPacket(const std::string& name, const FrameBuffers& frame) {
    return {name, true, frame.width(), frame.height(), displayChannels(frame)};
}

bool forEachTile(const FrameBuffers& frame, const std::string& name, int tileSize,
                 const std::function<bool(const UpdateImage&)>& send) {
    const std::vector<Layer> layers = displayLayers(frame);
    UpdateImage u;
    u.name = name;
    u.channels = displayChannels(frame);
    const std::size_t n = u.channels.size();
    tileSize = std::max(tileSize, 1);
    for (int y0 = 0; y0 < frame.height(); y0 += tileSize)
        for (int x0 = 0; x0 < frame.width(); x0 += tileSize) {
            u.x = x0;
            u.y = y0;
            u.width = std::min(tileSize, frame.width() - x0);
            u.height = std::min(tileSize, frame.height() - y0);
            u.pixels.resize(std::size_t(u.width) * std::size_t(u.height) * n);
            // Interleave the layers' channels pixel by pixel, in displayChannels' order.
            float* out = u.pixels.data();
            for (int y = y0; y < y0 + u.height; ++y)
                for (int x = x0; x < x0 + u.width; ++x)
                    for (Layer l : layers) {
                        const Image& image = frame.layer(l);
                        for (int c = 0; c < image.channels(); ++c) *out++ = image(x, y, c);
                    }
            if (!send(u)) return false;
        }
    return true;
}

Display::Display(DisplayOptions options)
    : m_options(std::move(options)),
      m_connection(m_options.address, m_options.warn),
      m_thread([this] { run(); }) {}

Display::~Display() {
    finish();
}

void Display::show(std::shared_ptr<const FrameBuffers> frame) {
    {
        std::lock_guard lock(m_mutex);
        if (m_finishing) return;
        m_pending = std::move(frame);
    }
    m_wake.notify_one();
}

void Display::finish() {
    {
        std::lock_guard lock(m_mutex);
        m_finishing = true;
    }
    m_wake.notify_one();
    if (m_thread.joinable()) m_thread.join();
}

bool Display::failed() const {
    return m_connection.failed();
}

void Display::send(const FrameBuffers& frame) {
    // Create the image the first time, and again when its size or layers changed.
    std::vector<std::string> channels = displayChannels(frame);
    if (channels != m_created || frame.width() != m_createdWidth ||
        frame.height() != m_createdHeight) {
        if (!m_connection.send(createPacket(m_options.name, frame))) return;
        m_created = std::move(channels);
        m_createdWidth = frame.width();
        m_createdHeight = frame.height();
    }
    forEachTile(frame, m_options.name, m_options.tileSize,
                [&](const UpdateImage& u) { return m_connection.send(u); });
}

void Display::run() {
    for (;;) {
        std::shared_ptr<const FrameBuffers> frame;
        bool finishing = false;
        {
            std::unique_lock lock(m_mutex);
            m_wake.wait(lock, [&] { return m_pending || m_finishing; });
            frame = std::move(m_pending);
            m_pending.reset();
            finishing = m_finishing;
        }
        if (frame && !m_connection.failed()) send(*frame);
        if (finishing) break;
    }
    if (m_options.closeAtEnd && !m_created.empty()) m_connection.send(CloseImage{m_options.name});
}

}  // namespace glint::tev
