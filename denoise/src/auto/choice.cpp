// The per-pixel choice of the automatic selection (choice.h; docs/auto.md, "Per-pixel choice").
#include "choice.h"

#include <algorithm>
#include <cmath>

#include "box_averages.h"
#include "estimator.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/progress.h"
#include "glint/image/error.h"
#include "options.h"
#include "score_rows.h"

namespace glint::denoise {

namespace detail {

Image boxSmooth(const Image& image, int radius, WorkContext* work) {
    GLINT_CHECK(image.channels() == 1 && radius >= 0);
    if (radius == 0 || image.empty()) return image;
    Image out(image.width(), image.height(), 1);
    boxAverages(
        image.width(), image.height(), radius, 1,
        [&](int x, int y, std::size_t) { return double(image(x, y, 0)); },
        [&](int x, int y, const double* mean) { out(x, y, 0) = float(mean[0]); }, nullptr, work);
    return out;
}

// One pass over the candidate's map and the baseline's. The sums are boxSmooth's, term for term
// and in its order, so the score is the same as smoothing stored d and d² maps, without storing
// them (nor the two averages).
Image windowScore(const Image& raw, const Image& base, int radius, double confidence) {
    const int w = raw.width(), h = raw.height();
    const std::size_t planes = confidence > 0.0 ? 2 : 1;
    Image score(w, h, 1);
    const double count = double((2 * radius + 1) * (2 * radius + 1));
    auto scoreOf = [&](float mean, float meanSq) {
        const double mu = mean;
        const double var = std::max(0.0, double(meanSq) - mu * mu);
        return float(mu + confidence * std::sqrt(var / count));
    };
    if (radius == 0) {  // boxSmooth returns the map itself
        for (std::size_t p = 0; p < score.data().size(); ++p) {
            const double v = double(raw.data()[p]) - double(base.data()[p]);
            score.data()[p] = planes == 1 ? float(v) : scoreOf(float(v), float(v * v));
        }
        return score;
    }
    boxAverages(
        w, h, radius, planes,
        [&](int x, int y, std::size_t k) {
            const double v = double(raw(x, y, 0)) - double(base(x, y, 0));
            return double(k == 0 ? float(v) : float(v * v));
        },
        [&](int x, int y, const double* means) {
            score(x, y, 0) =
                planes == 1 ? float(means[0]) : scoreOf(float(means[0]), float(means[1]));
        });
    return score;
}

double familywiseMargin(double confidence, std::size_t comparisons) {
    if (!(confidence > 0.0) || comparisons <= 1) return confidence;
    // Solve Φ(−z) = Φ(−confidence)/comparisons by bisection: Φ(−z) = erfc(z/√2)/2 falls
    // monotonically in z, and z lies between confidence and confidence + 40.
    const auto tail = [](double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); };
    const double target = tail(confidence) / double(comparisons);
    double lo = confidence, hi = confidence + 40.0;
    for (int i = 0; i < 100; ++i) {
        const double mid = 0.5 * (lo + hi);
        (tail(mid) > target ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

Image noiseLevel(const ErrorEstimator& estimator, const Rect& region, const Image& weight,
                 int window, WorkContext& work) {
    Image v(region.width(), region.height(), 1);
    work.parallelFor(0, region.height(), [&](int y) {
        for (int x = 0; x < region.width(); ++x) {
            double s = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double var = estimator.noiseVariance(x + region.x0, y + region.y0, c);
                s += var * (weight.empty() ? 1.0 : double(weight(x, y, c)));
            }
            v(x, y, 0) = float(s);
        }
    });
    return boxSmooth(v, window, &work);
}

namespace {

// The score of each candidate over the whole maps (of `radii`'s windows, the lowest: see
// choose), candidates through `work`.
std::vector<Image> windowScores(const std::vector<Image>& raws,
                                const std::vector<std::size_t>& candidates, std::size_t baseline,
                                const std::vector<int>& radii, double confidence,
                                WorkContext& work) {
    const std::size_t c = candidates.size();
    const Image& base = raws[candidates[baseline]];
    std::vector<Image> scores(c);
    work.parallelFor(
        0, int(c),
        [&](int index) {
            const auto j = std::size_t(index);
            const Image& raw = raws[candidates[j]];
            Image score;
            for (int radius : radii) {
                Image mean = windowScore(raw, base, radius, j != baseline ? confidence : 0.0);
                if (score.empty()) {
                    score = std::move(mean);
                } else {
                    for (std::size_t p = 0; p < score.data().size(); ++p)
                        score.data()[p] = std::min(score.data()[p], mean.data()[p]);
                }
            }
            scores[j] = std::move(score);
        },
        std::int64_t(radii.size()) * base.height());
    return scores;
}

// The per-pixel weights of rows [y0, y1) from `scores` (whose row 0 is row c0) into `out`'s
// planes (a final choice) and each row's wins and totals per candidate.
void weighRows(const std::vector<Image>& scores, int c0, int y0, int y1,
               const std::vector<std::size_t>& candidates, std::size_t baseline, double temperature,
               const Image& noise, bool final, Choice& out, std::vector<std::vector<int>>& rowWins,
               std::vector<std::vector<double>>& rowTotals, WorkContext& work) {
    const std::size_t c = candidates.size();
    const int width = scores.front().width();
    // The per-pixel weights over the candidates, in member order (deterministic). Rows
    // go in chunks of 64 pixels so that each candidate's scores are read and its weights
    // written as one run, not one value from each of c images per pixel. Only the final
    // choice keeps the weight planes; the first of a shortlist needs only each candidate's
    // pixels won and total weight (per row, then the rows in order).
    constexpr int kChunk = 64;
    work.parallelFor(y0, y1, [&](int y) {
        std::vector<double> s(c * kChunk);
        std::vector<float> w(c * kChunk);
        std::vector<int>& wins = rowWins[std::size_t(y)];
        std::vector<double>& rowTotal = rowTotals[std::size_t(y)];
        wins.assign(c, 0);
        rowTotal.assign(c, 0.0);
        for (int x0 = 0; x0 < width; x0 += kChunk) {
            const int pixelsHere = std::min(kChunk, width - x0);
            for (std::size_t j = 0; j < c; ++j) {
                const float* row = scores[j].row(y - c0) + x0;
                for (int k = 0; k < pixelsHere; ++k) s[j * kChunk + std::size_t(k)] = row[k];
            }
            std::fill(w.begin(), w.end(), 0.0f);
            for (int k = 0; k < pixelsHere; ++k) {
                const auto at = [&](std::size_t j) { return j * kChunk + std::size_t(k); };
                std::size_t best = baseline;
                for (std::size_t j = 0; j < c; ++j)
                    if (s[at(j)] < s[at(best)]) best = j;
                ++wins[best];
                const double unit =
                    temperature > 0.0 ? temperature * double(noise(x0 + k, y, 0)) : 0.0;
                if (!(unit > 0.0)) {
                    w[at(best)] = 1.0f;
                    continue;
                }
                double sum = 0.0;
                for (std::size_t j = 0; j < c; ++j) {
                    // exp(−6.91) < 1e-3: no exp for the many candidates that get weight 0.
                    const double x = (s[at(j)] - s[at(best)]) / unit;
                    const double e = x > 6.91 ? 0.0 : std::exp(-x);
                    w[at(j)] = e < 1e-3 ? 0.0f : float(e);
                    sum += w[at(j)];
                }
                for (std::size_t j = 0; j < c; ++j) w[at(j)] = float(w[at(j)] / sum);
            }
            for (std::size_t j = 0; j < c; ++j) {
                const float* run = w.data() + j * kChunk;
                for (int k = 0; k < pixelsHere; ++k) rowTotal[j] += run[k];
                if (final) std::copy(run, run + pixelsHere, out.planes[candidates[j]].row(y) + x0);
            }
        }
    });
}

}  // namespace

Choice choose(const Estimates& estimates, const std::vector<std::size_t>& candidates, bool final,
              const AutoSettings& settings, const Image& noise, WorkContext& work, int stripRows) {
    const std::vector<Image>& raws = estimates.maps;
    const std::vector<double>& mapMean = estimates.mapMean;
    const bool held = !estimates.mapRows;
    const std::size_t n = mapMean.size();
    const int width = held ? raws[candidates.front()].width() : estimates.width;
    const int height = held ? raws[candidates.front()].height() : estimates.height;
    // Maps read by rows go strip by strip.
    if (!held && stripRows <= 0) stripRows = height;
    const double temperature = settings.temperature;
    const std::size_t c = candidates.size();
    // The score of each candidate per pixel. The baseline is the candidate with the
    // smallest map mean over the region; another scores the smoothed difference to it plus
    // `confidence` standard errors of that local mean (from the difference's spread in the
    // window), so a pixel leaves the baseline only where the estimate says, with that
    // confidence, that another member is better there. With confidence 0 it is the plain
    // smoothed estimate. In the final choice, with `finer` > 0, the same is done in the
    // window halved `finer` times too, and the score is the lowest of them: a member that
    // is better by that margin in a smaller window wins there (docs/auto.md, "Per-pixel
    // choice").
    std::size_t baseline = 0;  // position in candidates
    for (std::size_t j = 0; j < c; ++j)
        if (mapMean[candidates[j]] < mapMean[candidates[baseline]]) baseline = j;
    std::vector<int> radii{settings.window};
    if (final)
        for (int k = 0; k < settings.finer && radii.back() > 1; ++k)
            radii.push_back(radii.back() / 2);
    // Every other candidate at every radius is one more chance to leave the baseline by noise:
    // with `familywise`, the margin keeps the family's chance at what `confidence` gives one.
    const double confidence = settings.familywise
                                  ? familywiseMargin(settings.confidence, (c - 1) * radii.size())
                                  : settings.confidence;
    // All rows at once, or strips of `stripRows` rows (the pipeline's tiles) whose
    // scores ScoreRows gives value for value as windowScore over the whole maps.
    Choice out;
    if (final) {
        out.planes.resize(n);
        for (std::size_t m : candidates) out.planes[m] = Image(width, height, 1);
    }
    std::vector<std::vector<int>> rowWins(static_cast<std::size_t>(height));
    std::vector<std::vector<double>> rowTotals(static_cast<std::size_t>(height));
    if (stripRows <= 0) {  // held maps
        const std::vector<Image> scores =
            windowScores(raws, candidates, baseline, radii, confidence, work);
        weighRows(scores, 0, 0, height, candidates, baseline, temperature, noise, final, out,
                  rowWins, rowTotals, work);
    } else {
        std::vector<ScoreRows> scoreRows;
        scoreRows.reserve(c);
        for (std::size_t j = 0; j < c; ++j)
            scoreRows.emplace_back(width, height, radii, j != baseline ? confidence : 0.0);
        for (int y0 = 0; y0 < height; y0 += stripRows) {
            const int y1 = std::min(height, y0 + stripRows);
            // The maps' rows the strip reads: the held maps, or those rows read.
            const int end = scoreRows.front().rowsReadEnd(y1);
            const auto rowsOf = [&](std::size_t m, Image& read) -> const Image& {
                if (held) return raws[m];
                read = estimates.mapRows(m, y0, end);
                return read;
            };
            const int rowsY0 = held ? 0 : y0;
            Image baseRead;
            const Image& base = rowsOf(candidates[baseline], baseRead);
            std::vector<Image> scores(c);
            work.parallelFor(
                0, int(c),
                [&](int j) {
                    Image read;
                    const Image& raw = std::size_t(j) == baseline
                                           ? base
                                           : rowsOf(candidates[std::size_t(j)], read);
                    Image& score = scores[std::size_t(j)];
                    score = Image(width, y1 - y0, 1);
                    scoreRows[std::size_t(j)].next(y0, y1, raw, base, rowsY0, score.data().data());
                },
                std::int64_t(radii.size()) * (y1 - y0));
            weighRows(scores, y0, y0, y1, candidates, baseline, temperature, noise, final, out,
                      rowWins, rowTotals, work);
        }
    }
    // Pixels won: where a candidate has the smallest score (the largest weight).
    out.wins.assign(n, 0);
    out.totals.assign(n, 0.0);
    for (std::size_t y = 0; y < rowWins.size(); ++y)
        for (std::size_t j = 0; j < c; ++j) {
            out.wins[candidates[j]] += rowWins[y][j];
            out.totals[candidates[j]] += rowTotals[y][j];
        }
    return out;
}

}  // namespace detail

}  // namespace glint::denoise
