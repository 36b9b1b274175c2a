// The automatic selection (auto.h, auto_stream.h; docs/auto.md, "Stages"; docs/auto-memory.md):
// one pipeline, tiled like OIDN's filter. The region is cut into strips of rows (tiles; the
// whole region is one tile when the memory budget allows, pipeline.h), each member is applied
// to one tile at a time (or its rows are read from a bank that holds them) and each tile is
// reduced at once to what the next stage needs, in passes over the frame:
//   1. the bank's median (all members on the input, per tile), when the error space needs it;
//   2. the error maps (all members on the halves, or SURE's applications), kept per member;
//   3. with a shortlist, its members on B (maps made symmetric);
//   4. feathering, the blend and the blends on the halves (the final candidates on the input
//      and the halves);
//   5. the stacking (its members on the input and the halves, read by rows, tile after tile).
// Between the passes, the stages that need whole-frame quantities (the choice's baseline and
// windows, the shortlist's counts, the blend's order, the display weights' floor) run on the
// kept one-channel maps. Every sum runs in the same order whatever the tiles, so one tile and
// many give the same floats. With the spill (strip_spill.h), a result that a later pass reads
// again is written to a temporary file and read back instead of filtered again; a member whose
// margin is large against the tiles (the learned member's) is applied once over the region
// and read from the spill by rows.
#include "glint/denoise/auto_stream.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <numeric>

#include "bank/bank_detail.h"
#include "blend.h"
#include "choice.h"
#include "display_weights.h"
#include "estimator.h"
#include "feathering.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/progress.h"
#include "glint/denoise/registry.h"
#include "glint/image/display_curve.h"
#include "glint/image/error.h"
#include "halves_estimator.h"
#include "median.h"
#include "options.h"
#include "pipeline.h"
#include "shortlist.h"
#include "stacking.h"
#include "strip_spill.h"
#include "sure_estimator.h"

namespace glint::denoise {

namespace detail {

namespace {

// A filter application counts as this many passes over its rows (as in auto_composite.cpp).
constexpr std::int64_t kFilterPasses = 4;

// Copies `rows` rows of `from` from row `fromY` on into `to` from row `toY` on (same width and
// channels).
void copyRows(const Image& from, int fromY, Image& to, int toY, int rows) {
    GLINT_CHECK(from.width() == to.width() && from.channels() == to.channels());
    const std::size_t values = std::size_t(from.width()) * std::size_t(from.channels());
    for (int r = 0; r < rows; ++r)
        std::memcpy(to.row(toY + r), from.row(fromY + r), values * sizeof(float));
}

// Each row's sum of a 1-channel map of rows from y0 on, into sums[y0 …] (meanPerChannel's).
void sumRows(const Image& rows, int y0, std::vector<double>& sums) {
    for (int y = 0; y < rows.height(); ++y) {
        double row = 0.0;
        for (int x = 0; x < rows.width(); ++x) row += rows(x, y, 0);
        sums[std::size_t(y0 + y)] = row;
    }
}

// meanPerChannel of a map from its row sums (sumRows), added in row order.
double meanOfRows(const std::vector<double>& sums, int width) {
    double total = 0.0;
    for (double row : sums) total += row;
    return total / double(std::size_t(width) * sums.size()) / 3.0;
}

// Rows [y0, y1) of a region-sized image.
Image rowsOf(const Image& image, int y0, int y1) {
    return image.crop(Rect{0, image.width(), y0, y1});
}

// The pipeline's state: the settings, the inputs the members see and the strips.
class Pipeline {
  public:
    // Rows [y0, y1) of the region, in region coordinates: one tile.
    struct Strip {
        int y0, y1;
    };

    Pipeline(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& s, int rows,
             int band, double memberMB, WorkContext& work, StripSpill& spill, StripSpill& mapSpill)
        : m_bank(bank),
          m_frame(frame),
          m_s(s),
          m_work(work),
          m_region(bank.region()),
          m_spill(spill),
          m_mapSpill(mapSpill),
          m_rows(std::max(1, rows)),
          m_band(std::max(0, band)),
          m_memberMB(memberMB) {
        for (int y = 0; y < m_region.height(); y += m_rows)
            m_strips.push_back({y, std::min(m_region.height(), y + m_rows)});
        // A member whose margins (read again above and below every tile) would cost more than
        // a quarter of its tile's rows is applied once over the region when the spill can keep
        // it (widePass).
        for (const BankMember& member : m_bank.members()) {
            const Filter& filter = findFilter(member.filter);
            const int margin = filter.margin(resolveParams(filter, member.params));
            m_wide.push_back(m_strips.size() > 1 && 8 * margin > m_rows ? 1 : 0);
        }
    }

    AutoResult run();

  private:
    Rect frameRect(int y0, int y1) const {
        return {m_region.x0, m_region.x1, m_region.y0 + y0, m_region.y0 + y1};
    }
    // Member m applied to `input` over region rows [y0, y1). A member with a memory budget of
    // its own (the learned member's memoryMB, whose tiling does not change its output) is held
    // to autoMemberMemoryMB.
    Image apply(std::size_t m, const FrameBuffers& input, int y0, int y1) const {
        const BankMember& member = m_bank.members()[m];
        const Filter& filter = findFilter(member.filter);
        FilterOptions fo;
        fo.region = frameRect(y0, y1);
        fo.progress = m_going;
        ParamValues params = resolveParams(filter, member.params);
        if (const auto it = params.find("memoryMB"); it != params.end())
            it->second = std::min(it->second, m_memberMB);
        return applyFilter(filter, input, params, fo);
    }
    // What a member is applied to: the input the bank sees, half A or half B.
    enum Side { Input = 0, HalfA = 1, HalfB = 2 };
    const FrameBuffers& inputOf(Side side) const {
        return side == Input ? *m_input : side == HalfA ? m_halves->halfA() : m_halves->halfB();
    }
    static std::int64_t keyOf(std::size_t m, Side side) { return std::int64_t(m) * 3 + side; }
    // Member m's result on `side` over region rows [y0, y1): the bank's rows when it holds
    // them, read from the spill when it holds them (a wide member's, widePass), else applied
    // (and spilled when `keep`: a later pass reads it again).
    Image memberResult(std::size_t m, Side side, int y0, int y1, bool keep) const {
        if (side == Input && !m_bank.results().empty()) return rowsOf(m_bank.result(m), y0, y1);
        Image out;
        if (m_spill.read(keyOf(m, side), y0, y1, out)) return out;
        out = apply(m, inputOf(side), y0, y1);
        if (keep) m_spill.write(keyOf(m, side), y0, out);
        return out;
    }
    // Member m's result on the input over `strip`: the bank's own image when it holds it and the
    // strip is the region (no copy), else memberResult's, held in `held`.
    const Image& inputResult(std::size_t m, const Strip& strip, Image& held) const {
        if (!m_bank.results().empty() && strip.y0 == 0 && strip.y1 == m_region.height())
            return m_bank.result(m);
        held = memberResult(m, Input, strip.y0, strip.y1, true);
        return held;
    }
    // Whether the reductions read the members' results from the spill in bands (m_band rows)
    // after a tile has applied them one at a time into it: then a tile holds the results of
    // the filters under way only, not every member's, and may be as tall as the budget allows.
    bool banded() const { return m_band > 0; }
    // Member m's result on `side` over `strip` into the spill unless it is there already.
    void spillResult(std::size_t m, Side side, const Strip& strip) const {
        if (m_spill.has(keyOf(m, side), strip.y0, strip.y1)) return;
        m_spill.write(keyOf(m, side), strip.y0, apply(m, inputOf(side), strip.y0, strip.y1));
    }
    // The bands of `strip`: the whole strip unless banded().
    std::vector<Strip> bandsOf(const Strip& strip) const {
        if (!banded()) return {strip};
        std::vector<Strip> bands;
        for (int y = strip.y0; y < strip.y1; y += m_band)
            bands.push_back({y, std::min(strip.y1, y + m_band)});
        return bands;
    }
    // The rows of the choice's score strips: the tiles', within kBandBytes of scores (a score
    // is a third of a result: three bands) whatever the tiles' height.
    int scoreRows() const { return std::min(m_rows, 3 * autoBandRows(m_bank, m_s)); }
    // Whether the error maps are kept in their spill file rather than held (storeMapRows, mapRows).
    bool mapsSpilled() const { return m_mapsInSpill; }
    // Rows [y0, y1) of member m's error map into its store (held or spilled).
    void storeMapRows(std::size_t m, int y0, const Image& rows) {
        if (mapsSpilled())
            m_mapSpill.write(std::int64_t(m), y0, rows);
        else
            copyRows(rows, 0, m_estimates.maps[m], y0, rows.height());
    }
    // Rows [y0, y1) of member m's error map (zeros from a spill that failed: then the passes
    // run again with the maps held, run()).
    Image mapRows(std::size_t m, int y0, int y1) const {
        if (!m_estimates.maps[m].empty()) return rowsOf(m_estimates.maps[m], y0, y1);
        Image rows;
        if (!m_mapSpill.read(std::int64_t(m), y0, y1, rows))
            rows = Image(m_region.width(), y1 - y0, 1);
        return rows;
    }
    // Forgets the spilled results of the members that `keep` refuses.
    void dropSpilled(const std::function<bool(std::size_t)>& keep) {
        for (std::size_t m = 0; m < m_bank.size(); ++m)
            if (!keep(m))
                for (Side side : {Input, HalfA, HalfB}) m_spill.drop(keyOf(m, side));
    }
    // fn(i) for i in [0, count) through the work context, a cancelled filter ending its index.
    void forEach(std::size_t count, std::int64_t units,
                 const std::function<void(std::size_t)>& fn) {
        m_work.parallelFor(
            0, int(count),
            [&](int i) {
                try {
                    fn(std::size_t(i));
                } catch (const Error& e) {
                    if (e.kind() == ErrorKind::Cancelled) return;
                    throw;
                }
            },
            units);
        m_work.throwIfCancelled();
    }
    std::int64_t filterUnits(const Strip& strip) const {
        return kFilterPasses * (strip.y1 - strip.y0);
    }

    void widePass();
    void medianPass();
    void estimatePass();
    void shortlistPass(const std::vector<std::size_t>& shortlist);
    void blendPass(std::vector<Image>& planes, AutoResult& result);
    void stackPass(const std::vector<int>& order, AutoResult& result);
    // The median's, its display values' and the tangent weights' rows of a strip.
    struct Centre {
        Image median, weight;
        std::vector<double> display;
    };
    Centre centreOf(const Strip& strip) const;

    const FilterBank& m_bank;
    const FrameBuffers& m_frame;
    const AutoSettings& m_s;
    WorkContext& m_work;
    const Rect m_region;
    StripSpill& m_spill;
    StripSpill& m_mapSpill;      // the error maps, 1 channel, when mapsSpilled()
    bool m_mapsInSpill = false;  // estimatePass's choice: the maps are in m_mapSpill
    const int m_rows;
    const int m_band;         // the reductions' bands (autoBandRows), 0: not banded
    const double m_memberMB;  // autoMemberMemoryMB
    std::vector<Strip> m_strips;
    std::vector<char> m_wide;  // per member: applied over the whole region (above)
    ProgressFn m_going = [this](double) { return !m_work.cancelled(); };

    FrameBuffers m_prefiltered;  // the bank's input when prefiltered (the halves)
    const FrameBuffers* m_input = nullptr;
    std::unique_ptr<HalvesEstimator> m_halves;
    std::unique_ptr<SureEstimator> m_sure;
    Image m_median, m_weight;
    std::vector<double> m_displayMedian;  // empty: each strip's is computed from its rows
    Estimates m_estimates;
    Image m_blendA, m_blendB;  // the blend's weights applied to the results on each half
};

// The wide members (m_wide) over the whole region on every side a later pass reads, into the
// spill, before the error maps take their memory: then no tile applies them again.
void Pipeline::widePass() {
    if (!m_spill.on()) return;
    std::vector<Side> sides;
    if (m_bank.results().empty()) sides.push_back(Input);
    if (m_halves) {
        sides.push_back(HalfA);
        // B too when the shortlist may read it (the wide member is usually among its best).
        if (m_s.bothHalves || m_s.shortlisted) sides.push_back(HalfB);
    }
    for (std::size_t m = 0; m < m_bank.size(); ++m) {
        if (!m_wide[m]) continue;
        for (Side side : sides) {
            m_spill.write(keyOf(m, side), 0, apply(m, inputOf(side), 0, m_region.height()));
            m_work.throwIfCancelled();
        }
    }
}

void Pipeline::medianPass() {
    const int width = m_region.width(), height = m_region.height();
    m_median = Image(width, height, 3);
    const std::size_t n = m_bank.size();
    for (const Strip& strip : m_strips) {
        // Banded: every member into the spill, one at a time, then the median band by band.
        if (banded())
            forEach(n, filterUnits(strip), [&](std::size_t m) { spillResult(m, Input, strip); });
        for (const Strip& band : bandsOf(strip)) {
            std::vector<Image> held(n);
            std::vector<const Image*> pointers(n);
            forEach(n, banded() ? 0 : filterUnits(band),
                    [&](std::size_t m) { pointers[m] = &inputResult(m, band, held[m]); });
            copyRows(medianOf(pointers, m_work), 0, m_median, band.y0, band.y1 - band.y0);
        }
    }
}

Pipeline::Centre Pipeline::centreOf(const Strip& strip) const {
    Centre c;
    if (m_median.empty()) return c;
    c.median = rowsOf(m_median, strip.y0, strip.y1);
    if (m_s.tangent) c.weight = rowsOf(m_weight, strip.y0, strip.y1);
    // D(median), value by value as displayOf gives it for the whole median.
    if (m_s.secant) c.display = displayOf(c.median, m_s.exposure);
    return c;
}

void Pipeline::estimatePass() {
    const int width = m_region.width(), height = m_region.height();
    const std::size_t n = m_bank.size();
    Estimates& e = m_estimates;
    e.maps.assign(n, Image{});
    e.width = width, e.height = height;
    e.mapRows = {};
    m_mapsInSpill = m_mapSpill.on();
    if (mapsSpilled())
        e.mapRows = [this](std::size_t m, int y0, int y1) { return mapRows(m, y0, y1); };
    else
        for (Image& map : e.maps) map = Image(width, height, 1);
    e.mapMean.assign(n, 0.0);
    // Each map's row sums (meanPerChannel's, row by row).
    std::vector<std::vector<double>> rowMeans(n, std::vector<double>(std::size_t(height), 0.0));
    e.estimatedMse.assign(n, 0.0);
    e.analytic.assign(n, 0);
    // The secant's unbiased terms per member and row, added up in row order as secantMap does.
    std::vector<std::vector<double>> unbiased(m_s.secant ? n : 0,
                                              std::vector<double>(std::size_t(height), 0.0));
    const std::int64_t sides = m_s.halves && m_s.bothHalves ? 2 : 1;
    for (const Strip& strip : m_strips) {
        const Centre c = centreOf(strip);
        const Image* weight = m_s.tangent ? &c.weight : nullptr;
        // The results on the halves are read again by the stacking's passes only.
        const bool keep = m_s.stack > 0;
        forEach(n, sides * filterUnits(strip), [&](std::size_t m) {
            Image map;
            std::vector<double> rowSums;
            if (m_halves) {
                const Image outA = memberResult(m, HalfA, strip.y0, strip.y1, keep);
                const Image outB =
                    m_s.bothHalves ? memberResult(m, HalfB, strip.y0, strip.y1, keep) : Image{};
                map = m_halves->mapOver(frameRect(strip.y0, strip.y1), true, outA,
                                        m_s.bothHalves ? &outB : nullptr, &c.median, &c.display,
                                        weight, rowSums);
            } else {
                // SURE's input is the bank's: the bank or the median's pass may hold it.
                Image held;
                const Image& out = inputResult(m, strip, held);
                MemberEstimate one =
                    m_sure->mapOver(m, frameRect(strip.y0, strip.y1), out, weight, m_going);
                map = std::move(one.map);
                e.analytic[m] = one.analytic ? 1 : 0;
            }
            sumRows(map, strip.y0, rowMeans[m]);
            storeMapRows(m, strip.y0, map);
            if (m_s.secant)
                std::copy(rowSums.begin(), rowSums.end(), unbiased[m].begin() + strip.y0);
        });
    }
    for (std::size_t m = 0; m < n; ++m) {
        e.mapMean[m] = meanOfRows(rowMeans[m], width);
        if (!m_s.secant) {
            e.estimatedMse[m] = e.mapMean[m];
            continue;
        }
        double total = 0.0;
        for (double v : unbiased[m]) total += v;
        e.estimatedMse[m] = total / double(width) / double(height) / 3.0;
    }
}

void Pipeline::shortlistPass(const std::vector<std::size_t>& shortlist) {
    Estimates& e = m_estimates;
    // The other members' maps are no longer read.
    for (std::size_t m = 0; m < e.maps.size(); ++m)
        if (!std::binary_search(shortlist.begin(), shortlist.end(), m)) {
            e.maps[m] = Image{};
            m_mapSpill.drop(std::int64_t(m));
        }
    std::vector<std::vector<double>> rowMeans(
        shortlist.size(), std::vector<double>(std::size_t(m_region.height()), 0.0));
    dropSpilled(
        [&](std::size_t m) { return std::binary_search(shortlist.begin(), shortlist.end(), m); });
    const std::size_t count = shortlist.size();
    std::vector<std::vector<double>> unbiased(
        m_s.secant ? count : 0, std::vector<double>(std::size_t(m_region.height()), 0.0));
    for (const Strip& strip : m_strips) {
        const Centre c = centreOf(strip);
        const Image* weight = m_s.tangent ? &c.weight : nullptr;
        forEach(count, filterUnits(strip), [&](std::size_t j) {
            const std::size_t m = shortlist[j];
            const Image outB = memberResult(m, HalfB, strip.y0, strip.y1, m_s.stack > 0);
            std::vector<double> rowSums;
            // B's term: the one-sided form with the halves' roles swapped.
            const Image mapB = m_halves->mapOver(frameRect(strip.y0, strip.y1), false, outB,
                                                 nullptr, &c.median, &c.display, weight, rowSums);
            Image raw = mapRows(m, strip.y0, strip.y1);
            for (int y = 0; y < raw.height(); ++y) {
                float* to = raw.row(y);
                const float* from = mapB.row(y);
                for (int x = 0; x < raw.width(); ++x)
                    to[x] = float(0.5 * (double(to[x]) + double(from[x])));
            }
            sumRows(raw, strip.y0, rowMeans[j]);
            storeMapRows(m, strip.y0, raw);
            if (m_s.secant)
                std::copy(rowSums.begin(), rowSums.end(), unbiased[j].begin() + strip.y0);
        });
    }
    for (std::size_t j = 0; j < count; ++j) {
        const std::size_t m = shortlist[j];
        e.mapMean[m] = meanOfRows(rowMeans[j], m_region.width());
        if (!m_s.secant) {
            e.estimatedMse[m] = e.mapMean[m];
            continue;
        }
        double total = 0.0;
        for (double v : unbiased[j]) total += v;
        const double onB = total / double(m_region.width()) / double(m_region.height()) / 3.0;
        e.estimatedMse[m] = 0.5 * (e.estimatedMse[m] + onB);
    }
}

// Feathering (featherRows), the blend (blendRows) and, for the stacking, the blends on the
// halves, strip by strip: each needs the members' results at the pixel only.
void Pipeline::blendPass(std::vector<Image>& planes, AutoResult& result) {
    const int width = m_region.width(), height = m_region.height();
    const std::size_t n = planes.size();
    std::vector<std::size_t> used;
    for (std::size_t m = 0; m < n; ++m)
        if (!planes[m].empty()) used.push_back(m);
    const bool stacking = m_s.stack > 0;
    // The blends on the halves: the stacking corrects them; the error estimate compares each
    // with the other half (B's only with both halves).
    const std::size_t sides = stacking || (m_s.estimateError && m_s.bothHalves) ? 3
                              : m_s.estimateError                               ? 2
                                                                                : 1;
    // Each plane feathered, before any is renormalised (members in parallel).
    std::vector<Image> feathered(m_s.feather > 0 ? used.size() : 0);
    if (m_s.feather > 0)
        m_work.parallelFor(
            0, int(used.size()),
            [&](int j) {
                feathered[std::size_t(j)] = boxSmooth(planes[used[std::size_t(j)]], m_s.feather);
            },
            height);
    result.composite = Image(width, height, 3);
    result.choice = Image(width, height, 1);
    if (sides > 1) m_blendA = Image(width, height, 3);
    if (sides > 2) m_blendB = Image(width, height, 3);
    for (const Strip& strip : m_strips) {
        // The used members' results on the input and, for the stacking, on each half: only
        // those of members with weight in the strip (feathered, which reaches further), since
        // every use below reads a result only where its weight is not 0.
        std::vector<char> needed(used.size(), 0);
        for (std::size_t j = 0; j < used.size(); ++j) {
            const Image& weights = m_s.feather > 0 ? feathered[j] : planes[used[j]];
            const auto begin = weights.data().begin() + std::ptrdiff_t(width) * strip.y0;
            const auto end = weights.data().begin() + std::ptrdiff_t(width) * strip.y1;
            needed[j] = std::any_of(begin, end, [](float w) { return w != 0.0f; }) ? 1 : 0;
        }
        const std::size_t count = used.size() * sides;
        // Banded: the needed results into the spill, one at a time, then read band by band.
        if (banded())
            forEach(count, filterUnits(strip), [&](std::size_t i) {
                if (needed[i % used.size()])
                    spillResult(used[i % used.size()], Side(i / used.size()), strip);
            });
        for (const Strip& band : bandsOf(strip)) {
            std::vector<Image> held(count);
            std::vector<const Image*> results(count, nullptr);
            forEach(count, banded() ? 0 : filterUnits(band), [&](std::size_t i) {
                const std::size_t j = i % used.size();
                const auto side = Side(i / used.size());
                if (!needed[j]) return;
                // Kept for the stacking, whose members are among these.
                if (side == Input) {
                    results[i] = &inputResult(used[j], band, held[i]);
                    return;
                }
                held[i] = memberResult(used[j], side, band.y0, band.y1, stacking);
                results[i] = &held[i];
            });
            std::vector<const Image*> full(n, nullptr), onA(n, nullptr), onB(n, nullptr);
            for (std::size_t j = 0; j < used.size(); ++j) {
                if (!needed[j]) continue;
                full[used[j]] = results[j];
                if (sides > 1) onA[used[j]] = results[used.size() + j];
                if (sides > 2) onB[used[j]] = results[2 * used.size() + j];
            }
            if (m_s.feather > 0)
                featherRows(planes, used, feathered, full, band.y0, band.y1, m_s.featherGate,
                            m_s.exposure, m_work);
            blendRows(planes, used, full, band.y0, band.y1, result.composite, &result.choice,
                      m_work);
            if (sides > 1)
                blendRows(planes, used, onA, band.y0, band.y1, m_blendA, nullptr, m_work);
            if (sides > 2)
                blendRows(planes, used, onB, band.y0, band.y1, m_blendB, nullptr, m_work);
        }
    }
}

// The stacking (stackComposite), as over the whole frame: the features' regressors over the
// frame, its members' results on the input and the halves read by rows, tile after tile.
void Pipeline::stackPass(const std::vector<int>& order, AutoResult& result) {
    std::vector<std::size_t> members;
    for (int m : order) {
        if (members.size() == std::size_t(m_s.stack)) break;
        members.push_back(std::size_t(m));
    }
    const std::size_t k = members.size();
    dropSpilled([&](std::size_t m) {
        return std::find(members.begin(), members.end(), m) != members.end();
    });
    // The features' regressors, from the whole frame's features around the composite and from
    // each half's around its blend (as the filters saw them: prefiltered when the bank was).
    // Each side's go to the spill (keys past the members') and are read back by rows; they are
    // held when the spill is off, and made again if a write failed.
    const FrameBuffers* sources[3] = {&inputOf(Input), &inputOf(HalfA), &inputOf(HalfB)};
    const Image* bases[3] = {&result.composite, &m_blendA, &m_blendB};
    // An image of the frame over the region: itself when the region is the frame (no copy).
    const auto regionOf = [&](const Image& image, Image& crop) -> const Image& {
        if (m_region == image.bounds()) return image;
        crop = image.crop(m_region);
        return crop;
    };
    // featureRegressors' arguments for `side`, then fn(base, albedo, normal).
    const auto withFeatures = [&](int side, const auto& fn) {
        Image albedoCrop, normalCrop;
        const Image* albedo =
            m_s.stackAlbedo ? &regionOf(sources[side]->layer(Layer::Albedo), albedoCrop) : nullptr;
        const Image* normal =
            m_s.stackNormal ? &regionOf(sources[side]->layer(Layer::Normal), normalCrop) : nullptr;
        return fn(*bases[side], albedo, normal);
    };
    const auto regressorsOf = [&](int side) {
        return withFeatures(side, [&](const Image& base, const Image* albedo, const Image* normal) {
            return featureRegressors(base, albedo, normal, m_s.stackFeatureWindow, &m_work);
        });
    };
    const auto featureKey = [&](std::size_t q, int side) {
        return keyOf(m_bank.size() + q, Side(side));
    };
    const std::size_t featureCount = (m_s.stackAlbedo ? 1 : 0) + (m_s.stackNormal ? 3 : 0);
    std::vector<Image> features[3];
    bool spilledFeatures[3] = {false, false, false};
    for (int side = 0; side < 3 && featureCount > 0; ++side) {
        // Strip by strip into the spill; held when the spill is off or a write failed.
        if (m_spill.on())
            withFeatures(side, [&](const Image& base, const Image* albedo, const Image* normal) {
                featureRegressorStrips(
                    base, albedo, normal, m_s.stackFeatureWindow, kStackTileRows,
                    [&](int y0, std::vector<Image>& rows) {
                        for (std::size_t q = 0; q < featureCount; ++q)
                            m_spill.write(featureKey(q, side), y0, rows[q]);
                    },
                    &m_work);
            });
        spilledFeatures[side] = m_spill.on();
        if (!spilledFeatures[side]) features[side] = regressorsOf(side);
    }
    // Rows [y0, y1) of feature regressor q on `side`: from the spill, or held.
    const auto featureRows = [&](std::size_t q, int side, int y0, int y1) {
        Image rows;
        if (spilledFeatures[side] && m_spill.read(featureKey(q, side), y0, y1, rows)) return rows;
        if (spilledFeatures[side])
            features[side] = regressorsOf(side), spilledFeatures[side] = false;
        return features[side][q].crop(Rect{0, m_region.width(), y0, y1});
    };
    const LoadStackRows load = [&](int y0, int y1, bool full, bool halves, StackRows& rows) {
        std::vector<Side> sides;
        if (full) sides.push_back(Input);
        if (halves) sides.push_back(HalfA), sides.push_back(HalfB);
        std::vector<Image> results(sides.size() * k);
        forEach(results.size(), kFilterPasses * (y1 - y0), [&](std::size_t i) {
            results[i] = memberResult(members[i % k], sides[i / k], y0, y1, false);
        });
        rows = StackRows{};
        for (std::size_t s = 0; s < sides.size(); ++s) {
            std::vector<Image>& to = sides[s] == Input   ? rows.full
                                     : sides[s] == HalfA ? rows.onA
                                                         : rows.onB;
            for (std::size_t j = 0; j < k; ++j) to.push_back(std::move(results[s * k + j]));
            for (std::size_t q = 0; q < featureCount; ++q)
                to.push_back(featureRows(q, int(sides[s]), y0, y1));
        }
    };
    // The regression, weighted by the display slope at the composite; a correction past the
    // feather gate or the noise gate is not applied (StackGate), the noise read from the frame's
    // variance of the mean when it has one.
    const Image weightAtC =
        m_s.space == SureSpace::Linear ? Image{} : tangentWeights(result.composite, m_s.exposure);
    Image cropVariance;
    StackGate gate{m_s.featherGate, m_s.exposure, m_s.stackNoiseGate, nullptr};
    if (const Image* variance = m_frame.find(Layer::Variance))
        gate.variance = &regionOf(*variance, cropVariance);
    // The halves' colour over the region.
    Image cropA, cropB;
    result.composite = stackComposite(
        std::move(result.composite), m_blendA, m_blendB, k + featureCount, load,
        regionOf(m_halves->halfA().color(), cropA), regionOf(m_halves->halfB().color(), cropB),
        weightAtC, m_s.stackWindow, m_s.stackRidge, m_s.stackFloor, m_s.stackSmooth, &m_work, gate);
    result.stacked = int(k);
    result.stackFeatures = int(featureCount);
}

AutoResult Pipeline::run() {
    const std::size_t n = m_bank.size();
    // The inputs the members see: the bank's (prefiltered when it was) and the halves, or SURE's
    // input and its perturbed copy.
    if (m_s.halves) {
        m_halves = std::make_unique<HalvesEstimator>(m_bank, m_frame, m_s, m_s.bothHalves,
                                                     &m_median, &m_displayMedian, nullptr);
        if (m_s.prefilter) m_prefiltered = prefilterFeatures(m_frame, m_s.prefilterParams);
        m_input = m_s.prefilter ? &m_prefiltered : &m_frame;
    } else {
        m_sure = std::make_unique<SureEstimator>(m_bank, m_frame, m_s, nullptr);
        m_input = &m_sure->filterInput();
    }

    // The members too wide for the tiles, once over the region.
    widePass();
    // Pass 1: the display linearisation around the bank's median.
    if (m_s.secant || m_s.tangent) {
        medianPass();
        m_weight = tangentWeights(m_median, m_s.exposure);
    }
    // The temperature's unit (before the maps, so that the weights it needs can go first).
    const ErrorEstimator& estimator =
        m_halves ? static_cast<const ErrorEstimator&>(*m_halves) : *m_sure;
    Image noise = m_s.temperature > 0.0
                      ? noiseLevel(estimator, m_region, m_weight, m_s.window, m_work)
                      : Image{};
    if (!m_s.tangent) m_weight = Image{};
    // Passes 2 and 3, again with the maps held if their spill failed on the way.
    std::vector<std::size_t> candidates;
    Choice chosen;
    do {
        // Pass 2: the error maps; the first choice.
        estimatePass();
        candidates.resize(n);
        std::iota(candidates.begin(), candidates.end(), std::size_t(0));
        chosen = choose(m_estimates, candidates, !m_s.shortlisted && !m_s.rechosen, m_s, noise,
                        m_work, scoreRows());
        // One-sided: the final choice again among the shortlist, on the same maps (a member
        // that wins only a few pixels, such as one that smears a small light, is not a
        // candidate).
        if (m_s.rechosen) {
            candidates = shortlistOf(chosen, std::size_t(m_s.shortlist));
            chosen = Choice{};
            chosen = choose(m_estimates, candidates, true, m_s, noise, m_work, scoreRows());
        }
        // Pass 3: the shortlist on B; the final choice.
        if (m_s.shortlisted) {
            candidates = shortlistOf(chosen, std::size_t(m_s.shortlist));
            chosen = Choice{};
            shortlistPass(candidates);
            chosen = choose(m_estimates, candidates, true, m_s, noise, m_work, scoreRows());
        }
    } while (m_mapsInSpill && m_mapSpill.failed());
    m_median = Image{}, m_weight = Image{}, m_displayMedian = {};
    m_estimates.maps = {}, m_estimates.mapRows = {};
    noise = Image{};
    for (std::size_t m = 0; m < n; ++m) m_mapSpill.drop(std::int64_t(m));
    dropSpilled([&](std::size_t m) { return !chosen.planes[m].empty(); });

    // Pass 4: feathering and the blend.
    std::vector<Image>& planes = chosen.planes;
    AutoResult result;
    blendPass(planes, result);
    std::vector<double> totals(n, 0.0);
    std::vector<int> order;
    for (std::size_t m = 0; m < n; ++m)
        if (!planes[m].empty()) totals[m] = meanPerChannel(planes[m]);
    for (std::size_t m = 0; m < n; ++m)
        if (totals[m] > 0.0) order.push_back(int(m));
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return totals[std::size_t(a)] > totals[std::size_t(b)]; });
    result.estimatedMse = m_estimates.estimatedMse;
    std::size_t best = candidates.front();
    for (std::size_t m : candidates)
        if (m_estimates.estimatedMse[m] < m_estimates.estimatedMse[best]) best = m;
    result.bestMember = int(best);
    for (char a : m_estimates.analytic) result.analytic.push_back(a != 0);
    result.estimator = m_s.estimator;

    // The blend's error per pixel, from its blends on the halves, before the stacking.
    if (m_s.estimateError) {
        // The unbiased form in linear values, each weighted by the display's squared secant
        // slope to the result: no bias from the display's curvature at a noisy half.
        result.error =
            secantCrossValidationMap(m_halves->halfA().color(), m_halves->halfB().color(), m_blendA,
                                     m_blendB.empty() ? nullptr : &m_blendB, m_region,
                                     result.composite, m_s.exposure, SecantForm::Unbiased);
        for (float& v : result.error.data()) v /= 3.0f;
        result.error = boxSmooth(result.error, m_s.window, &m_work);
        for (float& v : result.error.data()) v = std::max(v, 0.0f);
    }
    // Pass 5: the stacking.
    if (m_s.stack > 0) stackPass(order, result);
    for (int m : order) result.layers.push_back({m, std::move(planes[std::size_t(m)])});
    return result;
}

// The units the passes count, for the progress fraction (about: a stage that counts more makes the
// fraction wait at 0.999 until finish()).
std::int64_t expectedWork(const AutoSettings& s, std::size_t n, std::int64_t h) {
    const auto members = std::int64_t(n);
    const bool narrowed = s.shortlisted || s.rechosen;
    const auto shortlist = std::int64_t(narrowed ? s.shortlist : 0);
    const std::int64_t finalCandidates = narrowed ? shortlist : members;
    std::int64_t passes = 0;
    if (s.secant || s.tangent) passes += members * kFilterPasses + 1;
    passes += members * kFilterPasses * (s.halves && s.bothHalves ? 2 : 1);
    if (s.temperature > 0.0) passes += 3;
    passes += (narrowed ? members + 1 : 0) + (s.shortlisted ? shortlist * kFilterPasses : 0) +
              finalCandidates * (1 + s.finer) + 1;
    if (s.feather > 0) passes += finalCandidates + 2;
    passes += finalCandidates * kFilterPasses * (s.stack > 0 ? 3 : 1) + 1;
    if (s.stack > 0)
        passes += 3 * s.stack * kFilterPasses + 4 + (s.stackAlbedo || s.stackNormal ? 6 : 0);
    return passes * h;
}

}  // namespace

TiledAuto autoCompositeTiled(const FilterBank& bank, const FrameBuffers& frame,
                             const AutoOptions& options, const TileControl& control) {
    const AutoSettings settings = resolveSettings(bank, frame, options);
    const int height = bank.region().height();
    const std::uint64_t budget = autoMemoryBudget(options.memoryLimit);
    // The spill for at most every member's result on the input and on the halves that the
    // stacking reads.
    const std::size_t sides = settings.stack <= 0                            ? 1
                              : settings.bothHalves && !settings.shortlisted ? 3
                                                                             : 2;
    StripSpill spill;
    if (control.spill != SpillMode::Off)
        spill.open(StripSpill::directory(), bank.region().width(), height, 3, bank.size() * sides,
                   control.spill == SpillMode::Auto);
    // The error maps (one channel per member) in a spill of their own, unless the spill is off.
    StripSpill mapSpill;
    if (control.spill != SpillMode::Off)
        mapSpill.open(StripSpill::directory(), bank.region().width(), height, 1, bank.size(),
                      control.spill == SpillMode::Auto);
    // With the spill, the members are applied into it and read back by bands (Pipeline::banded).
    TileModel model =
        autoTileModel(bank, spill.on(), mapSpill.on(), tbb::this_task_arena::max_concurrency());
    if (control.bandRows > 0) model.banded = spill.on() && bank.results().empty();
    const int band = !model.banded          ? 0
                     : control.bandRows > 0 ? control.bandRows
                                            : autoBandRows(bank, settings);
    const int rows =
        std::min(height, control.rows > 0 ? control.rows
                                          : autoTileRows(bank, frame, settings, budget, model));
    WorkContext work(options.progress);
    work.expectWork(expectedWork(settings, bank.size(), height));
    TiledAuto out;
    try {
        work.addWork(0);  // the first report, at 0: a callback can stop before any work
        out.result =
            Pipeline(bank, frame, settings, rows, band,
                     autoMemberMemoryMB(bank, frame, settings, budget), work, spill, mapSpill)
                .run();
        work.throwIfCancelled();
        work.finish();
    } catch (const Error& e) {
        if (e.kind() == ErrorKind::Cancelled)
            throw Error(ErrorKind::Cancelled, "auto composite cancelled");
        throw;
    }
    out.result.tileRows = rows;
    out.bandRows = band;
    out.mapsSpilled = mapSpill.on();
    out.spillBytes = spill.bytesWritten();
    // Filtered again instead: a warning when the spill was asked for or a write failed.
    out.spilled = spill.on();
    if ((control.spill == SpillMode::On && !out.spilled) || spill.failed())
        out.warning = "the spill is off, the members are filtered again (same result, slower): " +
                      spill.warning();
    return out;
}

StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bankOptions,
                                   const AutoOptions& options, const TileControl& control) {
    StreamedAuto out;
    out.bank = bankWithoutResults(frame, bankOptions);
    TiledAuto tiled = autoCompositeTiled(out.bank, frame, options, control);
    out.result = std::move(tiled.result);
    out.spilled = tiled.spilled;
    out.warning = std::move(tiled.warning);
    return out;
}

}  // namespace detail

AutoResult autoComposite(const FilterBank& bank, const FrameBuffers& frame,
                         const AutoOptions& options) {
    return detail::autoCompositeTiled(bank, frame, options, {}).result;
}

StreamedAuto autoCompositeStreamed(const FrameBuffers& frame, const BankOptions& bank,
                                   const AutoOptions& options) {
    return detail::autoCompositeStreamed(frame, bank, options, {});
}

}  // namespace glint::denoise
