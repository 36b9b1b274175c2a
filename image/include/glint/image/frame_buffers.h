// glint::FrameBuffers — the named layers a render produces and the denoiser consumes.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "glint/image/image.h"

namespace glint {

/// The layers of a Glint frame (docs/image.md, "The layered EXR"). Every layer but Color may be
/// absent.
enum class Layer : int {
    Color,           ///< R,G,B: pixel mean of radiance
    Variance,        ///< variance.R/G/B: variance of the mean
    Albedo,          ///< albedo.R/G/B
    AlbedoVariance,  ///< albedoVariance.R/G/B
    Normal,          ///< normal.X/Y/Z: world-space shading normal
    NormalVariance,  ///< normalVariance.X/Y/Z
    Depth,           ///< depth.Z: camera-space z
    DepthVariance,   ///< depthVariance.Z
    Position,        ///< position.X/Y/Z: world space (optional)
    SampleCount,     ///< sampleCount.Y
    /// noisy.R/G/B: the render's colour where a denoiser replaced Color (glint-final's and
    /// glint-denoise's outputs, Cycles' "Noisy Image"); absent in a render (optional).
    Noisy,
    // Half buffers (glint-render --set halfBuffers=true; optional): the same statistics over the
    // pixel's odd-indexed samples only, half B of two independent halves.
    HalfColor,           ///< halfColor.R/G/B
    HalfVariance,        ///< halfVariance.R/G/B
    HalfAlbedo,          ///< halfAlbedo.R/G/B
    HalfAlbedoVariance,  ///< halfAlbedoVariance.R/G/B
    HalfNormal,          ///< halfNormal.X/Y/Z
    HalfNormalVariance,  ///< halfNormalVariance.X/Y/Z
    HalfDepth,           ///< halfDepth.Z
    HalfDepthVariance,   ///< halfDepthVariance.Z
    HalfSampleCount,     ///< halfSampleCount.Y
};
inline constexpr int kLayerCount = 20;

/// Static description of a layer: its EXR layer name and channel suffixes.
struct LayerInfo {
    Layer layer;
    std::string_view name;                     ///< "" for the root colour layer, else e.g. "albedo"
    int channels;                              ///< 3 or 1
    std::array<std::string_view, 3> suffixes;  ///< e.g. {"R","G","B"} or {"Z"}
};

/// Description of `layer`.
const LayerInfo& layerInfo(Layer layer);
/// The name users see and type: "color" for the root colour layer, else the EXR layer name
/// ("albedo", "depthVariance", ...).
std::string_view layerDisplayName(Layer layer);
/// The layer whose display name is `name` ("rgb" also names colour), or nullopt.
std::optional<Layer> findLayer(std::string_view name);
/// Full EXR channel name of channel `c` of `layer`, e.g. "albedoVariance.G" or "R".
std::string channelName(Layer layer, int c);
/// The layer whose variance `layer` is (Variance→Color...), or nullopt.
std::optional<Layer> varianceOf(Layer layer);
/// The variance layer of `layer` (Color→Variance...), or nullopt.
std::optional<Layer> varianceLayer(Layer layer);

/// The half-buffer layer holding half B's statistics of `layer` (Color→HalfColor,
/// Variance→HalfVariance … SampleCount→HalfSampleCount), or nullopt (position and noisy have
/// none).
std::optional<Layer> halfLayer(Layer layer);
/// True for the half-buffer layers (HalfColor … HalfSampleCount).
inline bool isHalfLayer(Layer layer) {
    return layer >= Layer::HalfColor;
}

/// FrameMetadata::extra key: the number of pixels whose variance of the mean lies below float's
/// normal range (1.2e-38) and so is held as 0 or a denormal (a scene of radiance about 1e-19 or
/// less). Absent when there are none. Variance-based estimators must not trust such a frame.
inline constexpr const char* kVarianceUnderflowKey = "varianceUnderflow";

/// What the renderer records about a frame; stored as glint:* EXR attributes.
struct FrameMetadata {
    int spp = 0;                        ///< glint:spp
    std::uint64_t seed = 0;             ///< glint:seed
    std::string integrator;             ///< glint:integrator ("path", "mlt", or foreign)
    std::string scene;                  ///< glint:scene (path of the scene file)
    std::string varianceOf = "mean";    ///< glint:varianceOf
    std::string normalSpace = "world";  ///< glint:normalSpace
    std::string depthKind = "cameraZ";  ///< glint:depth
    std::int64_t nonFiniteSamples = 0;  ///< glint:nonFiniteSamples (discarded NaN/Inf samples)
    std::string source = "glint";       ///< which naming convention the file used when read
    /// The file's layer the colour was read from: Noisy for the render a denoised file keeps
    /// (denoise::renderOf), HalfColor for half B (splitHalves), else Color. Not written; setting
    /// the colour resets it.
    Layer colorReadFrom = Layer::Color;
    /// Any other string attributes to carry through (key without the "glint:" prefix).
    std::map<std::string, std::string> extra;
};

/// The layers of one frame, all of the same size, plus metadata. A copy copies every layer; a
/// layer can also be shared with other frames without a copy (shareLayer, sharedCopy): it is
/// copied when one of them writes it (any non-const access), so each frame still sees the
/// values it had. Non-const references to a layer taken before it is shared must not be
/// written through afterwards, and a frame with shared layers must not be accessed non-const
/// from several threads at once.
class FrameBuffers {
  public:
    FrameBuffers() = default;
    /// A frame of the given size holding only a zero colour layer.
    FrameBuffers(int width, int height);
    FrameBuffers(const FrameBuffers& other);
    FrameBuffers& operator=(const FrameBuffers& other);
    FrameBuffers(FrameBuffers&&) noexcept = default;
    FrameBuffers& operator=(FrameBuffers&&) noexcept = default;

    int width() const { return m_width; }
    int height() const { return m_height; }

    bool has(Layer layer) const {
        const std::shared_ptr<Image>& held = m_layers[int(layer)];
        return held && !held->empty();
    }
    /// The layer; throws glint::Error(InvalidArgument) when absent.
    Image& layer(Layer layer);
    const Image& layer(Layer layer) const;
    /// The layer or nullptr when absent.
    const Image* find(Layer layer) const {
        return has(layer) ? m_layers[int(layer)].get() : nullptr;
    }
    Image* find(Layer layer) { return has(layer) ? &owned(layer) : nullptr; }

    Image& color() { return layer(Layer::Color); }
    const Image& color() const { return layer(Layer::Color); }

    /// Sets a layer; its size must match the frame and its channel count the layer's.
    void set(Layer layer, Image image);
    /// Sets `layer` to `from`'s layer `fromLayer` (same size and channel count), shared, not
    /// copied.
    void shareLayer(Layer layer, const FrameBuffers& from, Layer fromLayer);
    /// A frame with this one's metadata and every layer shared, none copied.
    FrameBuffers sharedCopy() const;
    /// Removes a layer (Color cannot be removed).
    void remove(Layer layer);
    /// Adds a zero layer of the right shape if absent; returns it.
    Image& ensure(Layer layer);

    FrameMetadata& metadata() { return m_metadata; }
    const FrameMetadata& metadata() const { return m_metadata; }

  private:
    // The layer, copied first when another frame shares it (copy-on-write); present.
    Image& owned(Layer layer);

    int m_width = 0;
    int m_height = 0;
    std::array<std::shared_ptr<Image>, kLayerCount> m_layers;
    FrameMetadata m_metadata;
};

/// How an error names `layer` of `frame` by the layer of its file: "the color", "the halfColor"
/// (also half B's colour, splitHalves), or, for a colour read from the noisy layer, "the noisy
/// layer (the render the file keeps)".
std::string layerInFile(const FrameBuffers& frame, Layer layer);
/// channelName of the file's layer that holds channel `c` of `layer` ("G", or "noisy.G").
std::string channelInFile(const FrameBuffers& frame, Layer layer, int c);

/// The two halves of a frame rendered with half buffers (docs/image.md, "Half buffers"), as
/// frames of their own without half layers: B from the half layers, A from the whole minus B
/// — per pixel and channel n_A = n − n_B, mean_A = (n·mean − n_B·mean_B)/n_A and, by Chan et
/// al.'s pairwise formula, M2_A = M2 − M2_B − (mean_B − mean_A)²·n_A·n_B/n, so A's variance
/// of the mean is that of its own samples (clamped at 0 against rounding). B's layers and the
/// layers A does not recompute (position) are the frame's, shared (FrameBuffers::shareLayer),
/// not copied; metadata is copied, with spp ⌈spp/2⌉ and ⌊spp/2⌋. Throws as checkHalves.
std::pair<FrameBuffers, FrameBuffers> splitHalves(const FrameBuffers& frame,
                                                  const std::string& file = {});
/// Whether splitHalves can split `frame`, without splitting it: throws Error(Format) naming
/// `file` and the first missing half layer, Error(InvalidArgument) when a half holds more
/// samples than the pixel.
void checkHalves(const FrameBuffers& frame, const std::string& file = {});

}  // namespace glint
