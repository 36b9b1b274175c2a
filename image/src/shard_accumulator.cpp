#include "shard_accumulator.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace glint::detail {

namespace {

/// Chan, Golub and LeVeque 1979, eq. 2.1: adds a group of `nb` samples with mean `meanB` and
/// sum of squared deviations `m2B` to a group of `n` samples with `mean` and `m2` (the caller
/// then sets n += nb, once for all channels of the pixel):
/// M2 = M2_A + M2_B + delta^2 n_A n_B / n.
inline void addGroup(double n, double nb, double meanB, double m2B, double& mean, double& m2) {
    const double total = n + nb;
    const double delta = meanB - mean;
    mean += delta * (nb / total);
    m2 += m2B + delta * delta * (n * nb / total);
}

}  // namespace

ShardAccumulator::ShardAccumulator(const FrameBuffers& first)
    : m_width(first.width()), m_height(first.height()) {
    const std::size_t pixels = std::size_t(m_width) * m_height;
    for (int l = 0; l < kLayerCount; ++l)
        if (first.has(Layer(l))) m_layers.push_back(Layer(l));
    // Each layer with its variance of the mean (M2 = V · n · (n − 1)); position has none.
    // Half-buffer layers weigh by the half's own count.
    m_halves = first.has(Layer::HalfSampleCount);
    for (Layer layer : m_layers) {
        if (layer == Layer::SampleCount || layer == Layer::HalfSampleCount || varianceOf(layer))
            continue;
        Target t;
        t.mean = layer;
        t.half = isHalfLayer(layer);
        if (const auto var = varianceLayer(layer); var && first.has(*var)) t.variance = var;
        t.channels = layerInfo(layer).channels;
        t.means.assign(pixels * t.channels, 0.0);
        if (t.variance) t.m2.assign(pixels * t.channels, 0.0);
        m_targets.push_back(std::move(t));
    }
    m_n.assign(pixels, 0.0);
    m_total.assign(pixels, 0.0);
    if (m_halves) m_nHalf.assign(pixels, 0.0), m_totalHalf.assign(pixels, 0.0);
}

void ShardAccumulator::add(const FrameBuffers& f) {
    const Image& counts = f.layer(Layer::SampleCount);
    const Image* halfCounts = m_halves ? &f.layer(Layer::HalfSampleCount) : nullptr;
    tbb::parallel_for(tbb::blocked_range<int>(0, m_height),
                      [&](const tbb::blocked_range<int>& rows) {
                          for (int y = rows.begin(); y != rows.end(); ++y)
                              for (int x = 0; x < m_width; ++x)
                                  addCounted(f, counts, halfCounts, x, y);
                      });
}

/// Folds pixel (x, y) of `f` into the whole and, with half buffers, into half B.
void ShardAccumulator::addCounted(const FrameBuffers& f, const Image& counts,
                                  const Image* halfCounts, int x, int y) {
    const std::size_t p = std::size_t(y) * m_width + x;
    if (halfCounts) {
        const double nbHalf = (*halfCounts)(x, y, 0);
        m_totalHalf[p] += nbHalf;
        if (nbHalf > 0.0) {
            addPixel(f, x, y, p, true, m_nHalf[p], nbHalf);
            m_nHalf[p] += nbHalf;
        }
    }
    const double nb = counts(x, y, 0);
    m_total[p] += nb;
    if (nb <= 0.0) return;
    addPixel(f, x, y, p, false, m_n[p], nb);
    m_n[p] += nb;
}

/// Folds pixel (x, y) of `f` (`nb` samples) into the targets of the whole (half = false) or of
/// half B (half = true), which hold `n` samples so far.
void ShardAccumulator::addPixel(const FrameBuffers& f, int x, int y, std::size_t p, bool half,
                                double n, double nb) {
    for (Target& t : m_targets) {
        if (t.half != half) continue;
        const Image& mean = f.layer(t.mean);
        const Image* variance = t.variance ? &f.layer(*t.variance) : nullptr;
        for (int c = 0; c < t.channels; ++c) {
            const std::size_t i = p * t.channels + c;
            const double var = variance ? (*variance)(x, y, c) : 0.0;
            double ignored = 0.0;
            addGroup(n, nb, mean(x, y, c), var * nb * std::max(nb - 1.0, 0.0), t.means[i],
                     t.variance ? t.m2[i] : ignored);
        }
    }
}

FrameBuffers ShardAccumulator::finish(const FrameMetadata& metadata) const {
    FrameBuffers out(m_width, m_height);
    for (Layer layer : m_layers) out.ensure(layer);
    out.metadata() = metadata;
    tbb::parallel_for(tbb::blocked_range<int>(0, m_height),
                      [&](const tbb::blocked_range<int>& rows) {
                          for (int y = rows.begin(); y != rows.end(); ++y)
                              for (int x = 0; x < m_width; ++x) finishPixel(out, x, y);
                      });
    return out;
}

void ShardAccumulator::finishPixel(FrameBuffers& out, int x, int y) const {
    const std::size_t p = std::size_t(y) * m_width + x;
    out.layer(Layer::SampleCount)(x, y, 0) = float(m_total[p]);
    if (m_halves) out.layer(Layer::HalfSampleCount)(x, y, 0) = float(m_totalHalf[p]);
    for (const Target& t : m_targets) {
        const double n = t.half ? m_nHalf[p] : m_n[p];
        for (int c = 0; c < t.channels; ++c) {
            const std::size_t i = p * t.channels + c;
            out.layer(t.mean)(x, y, c) = float(t.means[i]);
            if (t.variance)
                out.layer (*t.variance)(x, y, c) =
                    n > 1.0 ? float(t.m2[i] / (n * (n - 1.0))) : 0.0f;
        }
    }
}

}  // namespace glint::detail
