// The exact merge of shards' pixel statistics: per pixel the sample count, per channel the
// running mean and, for layers with a variance of the mean, the sum of squared deviations, all
// in double, folded input by input (Chan, Golub and LeVeque 1979). docs/distributed.md.
#pragma once

#include <optional>
#include <vector>

#include "glint/image/frame_buffers.h"

namespace glint::detail {

/// The running merge of frames of one size and one set of layers, added in shard order.
class ShardAccumulator {
  public:
    /// An empty merge of frames shaped as `first` (which is not added).
    explicit ShardAccumulator(const FrameBuffers& first);

    /// Folds one input (of the size and layers of the first) into the running merge.
    void add(const FrameBuffers& f);
    /// The merged frame: means, V = M2/(n(n−1)) and sampleCount = n, with `metadata`.
    FrameBuffers finish(const FrameMetadata& metadata) const;

  private:
    struct Target {
        Layer mean;
        bool half = false;  ///< a half-buffer layer (weighs by halfSampleCount)
        std::optional<Layer> variance;
        int channels = 0;
        std::vector<double> means, m2;
    };

    void addCounted(const FrameBuffers& f, const Image& counts, const Image* halfCounts, int x,
                    int y);
    void addPixel(const FrameBuffers& f, int x, int y, std::size_t p, bool half, double n,
                  double nb);
    void finishPixel(FrameBuffers& out, int x, int y) const;

    int m_width, m_height;
    std::vector<Layer> m_layers;
    std::vector<Target> m_targets;
    std::vector<double> m_n;                   ///< samples folded (inputs with a positive count)
    std::vector<double> m_total;               ///< sum of the sampleCounts
    bool m_halves = false;                     ///< the inputs have half buffers
    std::vector<double> m_nHalf, m_totalHalf;  ///< the same for half B (halfSampleCount)
};

}  // namespace glint::detail
