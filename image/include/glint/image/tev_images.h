// The images a tev client builds in Glint (the studio's listener, docs/studio.md "Receiving
// images"): CreateImage makes one, UpdateImage fills tiles of it, CloseImage completes it; each
// is readable at any time as a frame whose layers are found by their channel names, as a
// layered EXR's are.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"
#include "glint/image/tev_protocol.h"

namespace glint::tev {

/// What a packet did to the images.
struct Change {
    enum Kind { None, Created, Updated, Closed };
    Kind kind = None;
    std::string name;
};

class ReceivedImages {
  public:
    /// Applies `packet`. OpenImage, ReloadImage and VectorGraphics change nothing (Kind None).
    /// Throws glint::Error (nothing changes then): InvalidArgument for an update or close of an
    /// image not created, a tile outside the image, a channel the image lacks or a channel
    /// named twice; OutOfMemory when a new image would need more than `memoryLimit` bytes (0:
    /// what is available).
    Change apply(const Packet& packet, std::uint64_t memoryLimit = 0);

    bool has(const std::string& name) const { return m_images.count(name) > 0; }
    /// Whether a CloseImage completed it.
    bool complete(const std::string& name) const;
    /// The image `name` as a frame: channels named as in a layered EXR (Glint's, pbrt-v4's,
    /// Cycles', Mitsuba's) fill their layers; without R,G,B its first channels (or its one
    /// channel, as grey) are the colour. A per-sample variance (pbrt-v4's) is left out, its
    /// sample count unknown. Throws glint::Error(InvalidArgument) for an unknown name.
    FrameBuffers frame(const std::string& name) const;
    /// Forgets an image (a completed one, once read).
    void forget(const std::string& name) { m_images.erase(name); }

  private:
    struct Received {
        std::vector<std::string> channels;
        Image pixels;  // all channels interleaved, in `channels` order
        bool complete = false;
    };
    const Received& find(const std::string& name) const;

    std::map<std::string, Received> m_images;
};

}  // namespace glint::tev
