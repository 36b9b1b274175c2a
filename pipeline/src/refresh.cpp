// The steering loop's refresh (refresh.h): auto on the frame so far, its error made relative, and
// the importance map of the next adaptive passes.
#include "glint/pipeline/refresh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include <tbb/task_arena.h>

#include "glint/denoise/auto_stream.h"
#include "glint/image/box_mean.h"
#include "glint/image/error.h"
#include "glint/pipeline/steering.h"

namespace glint::pipeline {

namespace {

/// relMSE's floor of the reference's square (glint::relMse).
constexpr double kRelativeFloor = 0.01;

/// The radius of the neighbourhood a provisional map scores a pixel on.
constexpr int kNeighbourhood = 2;

/// Sets `weights` to 0 outside the worst `focus` of the pixels by `score` (focus 1: none): exactly
/// ⌈focus · pixels⌉ stay open, equal scores taken in pixel order (a neighbourhood's mean makes
/// ties common), a NaN score the best.
void keepWorst(Image& weights, const Image& score, double focus) {
    if (focus >= 1.0) return;
    const auto s = score.data();
    const std::size_t n = s.size();
    const std::size_t keep =
        std::min(n, std::max<std::size_t>(1, std::size_t(std::ceil(focus * double(n)))));
    auto key = [&](std::size_t i) {
        return std::isnan(s[i]) ? -std::numeric_limits<float>::infinity() : s[i];
    };
    std::vector<std::size_t> order(n);
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::nth_element(order.begin(), order.begin() + std::ptrdiff_t(keep - 1), order.end(),
                     [&](std::size_t a, std::size_t b) {
                         return key(a) > key(b) || (key(a) == key(b) && a < b);
                     });
    std::vector<char> open(n, 0);
    for (std::size_t i = 0; i < keep; ++i) open[order[i]] = 1;
    for (std::size_t i = 0; i < n; ++i)
        if (!open[i]) weights.data()[i] = 0.0f;
}

}  // namespace

double meanSpp(const FrameBuffers& frame) {
    double sum = 0.0;
    for (float n : frame.layer(Layer::SampleCount).data()) sum += double(n);
    return sum / double(std::size_t(frame.width()) * std::size_t(frame.height()));
}

AutoRun autoRun(const denoise::AutoOptions& options, denoise::AutoQuality quality, int bankSize,
                const std::vector<std::string>& filters) {
    AutoRun run;
    run.autoOptions = options;
    run.autoOptions.estimateError = true;
    if (run.autoOptions.tuning.empty())
        run.autoOptions.tuning = denoise::autoQualityTuning(quality);
    run.bank.size = bankSize > 0 ? bankSize : denoise::autoQualityBankSize(quality);
    run.bank.filters = filters;
    run.bank.prefilter = run.autoOptions.prefilter;
    run.bank.prefilterParams = run.autoOptions.prefilterParams;
    return run;
}

Denoised denoiseFrame(const FrameBuffers& frame, const AutoRun& run) {
    const auto start = std::chrono::steady_clock::now();
    Denoised d;
    d.meanSpp = meanSpp(frame);
    d.result = denoise::autoCompositeStreamed(frame, run.bank, run.autoOptions).result;
    d.relative = relativeError(d.result.error, d.result.composite, run.autoOptions.exposure);
    d.relMse = estimatedRelMse(d.relative);
    d.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return d;
}

Refresher::Refresher(RefreshOptions options)
    : m_options(std::move(options)),
      m_run(autoRun(m_options.autoOptions, m_options.quality, m_options.bankSize,
                    m_options.filters)) {
    GLINT_CHECK(m_options.growth > 1.0 && m_options.focus > 0.0 && m_options.focus <= 1.0 &&
                    m_options.threads >= 0,
                "a refresh growth above 1, a focus in (0, 1] and threads at least 0");
}

bool Refresher::due(const FrameBuffers& frame) const {
    return !m_last || meanSpp(frame) >= m_options.growth * m_last->meanSpp;
}

Denoised Refresher::denoise(const FrameBuffers& frame) const {
    if (m_options.threads == 0) return denoiseFrame(frame, m_run);
    // No thread outside the arena joins its work (one slot reserved for this one).
    tbb::task_arena arena(m_options.threads, 1);
    return arena.execute([&] { return denoiseFrame(frame, m_run); });
}

void Refresher::adopt(Denoised denoised) {
    if (m_refreshes == 0) m_startSpp = denoised.meanSpp;
    ++m_refreshes;
    m_autoSeconds += denoised.seconds;
    m_last = std::move(denoised);
}

std::shared_ptr<const Image> Refresher::map() const {
    GLINT_CHECK(m_last.has_value(), "an importance map after a refresh");
    const Image& relative = m_last->relative;
    // The threshold follows the renderer's error, which falls as 1/sqrt(spp): the schedule's
    // scale keeps about as many pixels open as at the start.
    const double scale = std::sqrt(m_last->meanSpp / m_startSpp);
    Image weights = m_options.varianceOnly
                        ? Image(relative.width(), relative.height(), 1, float(scale))
                        : importanceFromError(relative, scale);
    keepWorst(weights, relative, m_options.focus);
    return std::make_shared<const Image>(std::move(weights));
}

std::shared_ptr<const Image> Refresher::provisional(const FrameBuffers& frame, double share) const {
    GLINT_CHECK(share > 0.0 && share <= 1.0, "a provisional map's share in (0, 1]");
    // Scored on 5 × 5 neighbourhoods: a pixel's own samples are a 25th of what opens it. Scored
    // on its own samples alone, the pixels left closed are those whose few samples missed the
    // rare bright paths, and they keep them: the frame ran 1 % dark (docs/lab/adaptive-bias.md).
    // Scored on half B alone when the frame has it, as the renderer's threshold decides (its
    // adaptiveError half): half A never decides and stays unbiased, and the frame's bias is
    // half B's share (Keep Refining's frame −0.08 % at its end against −0.14 %, same page).
    const bool halves = frame.has(Layer::HalfColor) && frame.has(Layer::HalfVariance);
    const Image colour =
        boxMean(frame.layer(halves ? Layer::HalfColor : Layer::Color), kNeighbourhood);
    const Image variance =
        boxMean(frame.layer(halves ? Layer::HalfVariance : Layer::Variance), kNeighbourhood);
    Image relative(frame.width(), frame.height(), 1);
    for (int y = 0; y < frame.height(); ++y)
        for (int x = 0; x < frame.width(); ++x) {
            double sum = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double v = double(colour(x, y, c));
                sum += double(variance(x, y, c)) / (v * v + kRelativeFloor);
            }
            relative(x, y, 0) = std::isfinite(sum) ? float(sum / 3.0) : 0.0f;
        }
    Image weights(frame.width(), frame.height(), 1, 1.0f);
    keepWorst(weights, relative, share * m_options.focus);
    return std::make_shared<const Image>(std::move(weights));
}

std::shared_ptr<const Image> Refresher::importance(const FrameBuffers& frame) {
    if (!due(frame)) return nullptr;
    adopt(denoise(frame));
    return map();
}

bool Refresher::grew(const FrameBuffers& frame) const {
    return !m_last || meanSpp(frame) > m_last->meanSpp;
}

std::shared_ptr<const Image> Refresher::converged(const FrameBuffers& frame) {
    if (!grew(frame)) return nullptr;
    adopt(denoise(frame));
    return map();
}

}  // namespace glint::pipeline
