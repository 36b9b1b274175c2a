// The U-Net of Open Image Denoise's RT filter (OIDN 2.x, training/model.py and
// core/unet_filter.cpp): the base, small and large variants built from a weight blob and run on
// the CPU with oneDNN convolutions.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "learned/tza.h"

namespace glint::denoise::learned {

/// Sizes of tiles the network takes: width and height are multiples of this.
inline constexpr int kUNetAlignment = 16;

/// Memory for a network's activations, reused by every run() given it (e.g. all tiles of one
/// frame): it grows to the largest tile's need and is backed by huge pages where the system
/// allows, so that its pages are touched once. Not thread-safe: one per concurrent run.
class UNetWorkspace {
  public:
    UNetWorkspace() = default;
    UNetWorkspace(const UNetWorkspace&) = delete;
    UNetWorkspace& operator=(const UNetWorkspace&) = delete;
    /// At least `bytes` bytes, 2 MiB-aligned; the contents of earlier calls are not kept.
    std::byte* reserve(std::size_t bytes);
    std::size_t size() const { return m_size; }

  private:
    struct Free {
        void operator()(std::byte* p) const;
    };
    std::unique_ptr<std::byte, Free> m_data;
    std::size_t m_size = 0;
};

/// A U-Net with its weights, ready to run on tiles of any size (a multiple of 16). Thread-safe:
/// run() may be called concurrently.
class UNetNetwork {
  public:
    /// Checks the tensors against the U-Net variant they describe (base, small or large, told
    /// apart as OIDN does) for `inputChannels` (3, 6 or 9) input channels; throws
    /// glint::Error(Format) naming `file` and the first tensor that does not fit.
    UNetNetwork(const TzaTensors& tensors, int inputChannels, const std::string& file);
    ~UNetNetwork();
    UNetNetwork(const UNetNetwork&) = delete;
    UNetNetwork& operator=(const UNetNetwork&) = delete;

    int inputChannels() const { return m_inputChannels; }
    /// "base", "small" or "large".
    const std::string& variant() const { return m_variant; }
    /// Border a tile needs around the pixels it outputs so that they equal a single pass:
    /// OIDN's receptive-field half-width rounded up to the alignment (96 base, 112 large).
    int overlap() const;
    /// Multiply-adds per pixel of all convolutions (×2 for FLOPs).
    double macsPerPixel() const;
    /// Bytes of activations per pixel of a tile (oneDNN's chosen memory formats, buffers shared
    /// between tensors whose lifetimes do not overlap).
    double bytesPerPixel() const;

    /// Called after each layer with the number of layers done and the total; may throw to stop.
    using LayerFn = std::function<void(int done, int total)>;

    /// Writes a tile's input: h × w pixels of inputChannels() interleaved floats, row-major,
    /// every value (the padding's zeros too).
    using FillFn = std::function<void(float* input)>;
    /// Reads a tile's output: h × w pixels of 3 interleaved floats, row-major.
    using ReadFn = std::function<void(const float* output)>;

    /// Runs the network on one tile of h × w pixels (multiples of 16): `fill` writes its input,
    /// `read` reads its output, both in place in `workspace` (where the activations live) when
    /// oneDNN keeps them interleaved, as it does on AVX-512 (else through a reorder). Uses
    /// `threads` OpenMP threads inside oneDNN.
    void run(int h, int w, const FillFn& fill, const ReadFn& read, int threads,
             UNetWorkspace& workspace, const LayerFn& afterLayer = {}) const;

  private:
    struct Layer;
    struct Plan;
    std::shared_ptr<const Plan> plan(int h, int w) const;

    int m_inputChannels = 0;
    std::string m_variant;
    std::vector<Layer> m_layers;
    mutable std::mutex m_mutex;
    mutable std::vector<std::pair<std::pair<int, int>, std::shared_ptr<const Plan>>> m_plans;
};

}  // namespace glint::denoise::learned
