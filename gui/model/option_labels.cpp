#include "model/option_labels.h"

#include <QObject>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "glint/denoise/registry.h"
#include "model/layer_names.h"

namespace glint::studio {

namespace {

// The registered filter called `name`, or nullptr.
const denoise::Filter* registeredFilter(const std::string& name) {
    for (const denoise::Filter* f : denoise::allFilters())
        if (f->name() == name) return f;
    return nullptr;
}

// A numeric parameter's value in `params`, its default when absent.
double valueOf(const denoise::ParamSpec& spec, const denoise::ParamValues& params) {
    const auto it = params.find(spec.name);
    return it == params.end() ? spec.defaultValue : it->second;
}

// How far apart `values` lie, as a fraction of the parameter's soft range (in log units for a
// log-scaled one): 0 for equal values.
double spreadOf(const denoise::ParamSpec& spec, const std::vector<double>& values) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    if (*hi == *lo) return 0.0;
    if (spec.isChoice()) return 1.0;
    if (spec.scale == ParamScale::Log && *lo > 0.0 && spec.softMin > 0.0)
        return std::log(*hi / *lo) / std::max(std::log(spec.softMax / spec.softMin), 1e-9);
    return (*hi - *lo) / std::max(spec.softMax - spec.softMin, 1e-12);
}

// Values as text with the fewest significant digits (2 or 3) that keep distinct values apart.
std::vector<QString> roundedTexts(const denoise::ParamSpec& spec,
                                  const std::vector<double>& values) {
    std::vector<QString> texts;
    for (int digits : {2, 3}) {
        texts.clear();
        for (double v : values) texts.push_back(paramValueText(spec, v, digits));
        std::set<QString> distinctTexts(texts.begin(), texts.end());
        std::set<double> distinctValues(values.begin(), values.end());
        if (distinctTexts.size() == distinctValues.size()) break;
    }
    return texts;
}

// The lines of each option of one filter (`indices` into `options`, two or more): the
// parameters whose values differ among them.
void labelGroup(const std::vector<OptionMember>& options, const std::vector<std::size_t>& indices,
                std::vector<QStringList>& labels) {
    const denoise::Filter& f = *registeredFilter(options[indices.front()].filter);
    struct Differing {
        const denoise::ParamSpec* spec;
        std::vector<double> values;
        double spread;
    };
    std::vector<Differing> differing;
    for (const denoise::ParamSpec& spec : f.params()) {
        if (spec.isStrings || spec.isColour) continue;
        std::vector<double> values;
        for (std::size_t i : indices) values.push_back(valueOf(spec, options[i].params));
        // Less than 2 % of the soft range apart: the same to the eye.
        const double spread = spreadOf(spec, values);
        if (spread > 0.02) differing.push_back({&spec, values, spread});
    }
    std::stable_sort(differing.begin(), differing.end(),
                     [](const Differing& a, const Differing& b) { return a.spread > b.spread; });
    if (differing.size() > 2) differing.resize(2);
    for (std::size_t k = 0; k < indices.size(); ++k) {
        QStringList& lines = labels[indices[k]];
        if (differing.empty()) lines << QObject::tr("same settings");
        for (const Differing& d : differing)
            lines << QStringLiteral("%1 %2").arg(shortParamLabel(*d.spec),
                                                 roundedTexts(*d.spec, d.values)[k]);
    }
}

// Luminance (Rec. 709) of pixel (x, y).
double luminanceAt(const Image& image, int x, int y) {
    if (image.channels() < 3) return image(x, y, 0);
    return 0.2126 * image(x, y, 0) + 0.7152 * image(x, y, 1) + 0.0722 * image(x, y, 2);
}

// A grid step reading at most 2^16 pixels of a width × height image.
int gridStep(int width, int height) {
    const double pixels = double(width) * double(height);
    return std::max(1, int(std::ceil(std::sqrt(pixels / 65536.0))));
}

}  // namespace

std::vector<QStringList> distinguishingLabels(const std::vector<OptionMember>& options) {
    std::vector<QStringList> labels(options.size());
    std::map<std::string, std::vector<std::size_t>> byFilter;
    for (std::size_t i = 0; i < options.size(); ++i) byFilter[options[i].filter].push_back(i);
    for (const auto& [filter, indices] : byFilter) {
        for (std::size_t i : indices) labels[i] << filterTitle(filter);
        if (indices.size() > 1 && registeredFilter(filter)) {
            labelGroup(options, indices, labels);
            continue;
        }
        // Alone of its filter: its main parameter, as a choice is named.
        for (std::size_t i : indices) {
            const QString name = choiceName(filter, options[i].params);
            const QString title = filterTitle(filter);
            if (name.size() > title.size() + 2) labels[i] << name.mid(title.size() + 2);
        }
    }
    return labels;
}

QStringList distinctNames(const std::vector<OptionMember>& members) {
    QStringList names;
    for (const OptionMember& m : members) names << layerName(m.filter, m.params);
    // The indices of each name that more than one member has.
    auto sharedNames = [&names] {
        std::map<QString, std::vector<std::size_t>> byName;
        for (std::size_t i = 0; i < std::size_t(names.size()); ++i)
            byName[names[qsizetype(i)]].push_back(i);
        std::erase_if(byName, [](const auto& entry) { return entry.second.size() < 2; });
        return byName;
    };
    // 1. Members sharing a name: the parameters that differ among them.
    for (const auto& [name, indices] : sharedNames()) {
        std::vector<OptionMember> group;
        for (std::size_t i : indices) group.push_back(members[i]);
        const std::vector<QStringList> labels = distinguishingLabels(group);
        for (std::size_t k = 0; k < indices.size(); ++k) {
            const QStringList differing = labels[k].mid(1);  // after the filter's title
            if (!differing.isEmpty() && differing.front() != QObject::tr("same settings"))
                names[qsizetype(indices[k])] += QStringLiteral(" (%1)").arg(differing.join(", "));
        }
    }
    // 2. Still alike (the same settings, or differing beyond the two widest parameters): the
    // member's number.
    for (const auto& [name, indices] : sharedNames())
        for (std::size_t i : indices) names[qsizetype(i)] += QStringLiteral(" #%1").arg(i + 1);
    return names;
}

OptionContrast contrastOf(const std::vector<const Image*>& images) {
    OptionContrast c;
    c.words.assign(images.size(), QString());
    if (images.size() < 2) return c;
    const Image& first = *images.front();
    for (const Image* image : images)
        if (image->width() != first.width() || image->height() != first.height()) return c;
    const int step = gridStep(first.width(), first.height());
    std::vector<double> detail(images.size(), 0.0), mean(images.size(), 0.0);
    std::vector<std::vector<double>> lum(images.size());
    for (std::size_t i = 0; i < images.size(); ++i) {
        const Image& im = *images[i];
        double gradient = 0.0;
        for (int y = 0; y + 1 < im.height(); y += step)
            for (int x = 0; x + 1 < im.width(); x += step) {
                const double l = luminanceAt(im, x, y);
                if (!std::isfinite(l)) continue;
                lum[i].push_back(l);
                const double dx = luminanceAt(im, x + 1, y) - l, dy = luminanceAt(im, x, y + 1) - l;
                if (std::isfinite(dx) && std::isfinite(dy)) gradient += std::hypot(dx, dy);
            }
        double sum = 0.0;
        for (double l : lum[i]) sum += l;
        mean[i] = lum[i].empty() ? 0.0 : sum / double(lum[i].size());
        detail[i] =
            lum[i].empty() || mean[i] <= 0.0 ? 0.0 : gradient / double(lum[i].size()) / mean[i];
    }
    // The largest mean relative difference of two options (their samples are on one grid).
    for (std::size_t a = 0; a < images.size(); ++a)
        for (std::size_t b = a + 1; b < images.size(); ++b) {
            if (lum[a].size() != lum[b].size() || lum[a].empty()) continue;
            double diff = 0.0;
            for (std::size_t k = 0; k < lum[a].size(); ++k) diff += std::abs(lum[a][k] - lum[b][k]);
            const double scale = 0.5 * (mean[a] + mean[b]) * double(lum[a].size());
            if (scale > 0.0) c.maxDifference = std::max(c.maxDifference, diff / scale);
        }
    c.nearIdentical = c.maxDifference < kNearIdentical;
    // The extremes of detail, when it differs by 5 % or more.
    const auto [lo, hi] = std::minmax_element(detail.begin(), detail.end());
    if (*hi > 0.0 && (*hi - *lo) / *hi >= 0.05 && !c.nearIdentical) {
        c.words[std::size_t(hi - detail.begin())] = QObject::tr("most detail");
        c.words[std::size_t(lo - detail.begin())] = QObject::tr("smoothest");
    }
    return c;
}

Rect mostDifferentWindow(const std::vector<const Image*>& images, int side) {
    if (images.empty()) return {};
    const Image& first = *images.front();
    const Rect whole{0, first.width(), 0, first.height()};
    if (images.size() < 2 || (first.width() <= side && first.height() <= side)) return whole;
    for (const Image* image : images)
        if (image->width() != first.width() || image->height() != first.height()) return whole;
    // The variance across the options on a grid, then its summed-area table.
    const int step = gridStep(first.width(), first.height());
    const int gw = (first.width() + step - 1) / step, gh = (first.height() + step - 1) / step;
    std::vector<double> sat(std::size_t(gw + 1) * std::size_t(gh + 1), 0.0);
    auto at = [&](int x, int y) -> double& {
        return sat[std::size_t(y) * std::size_t(gw + 1) + std::size_t(x)];
    };
    for (int gy = 0; gy < gh; ++gy)
        for (int gx = 0; gx < gw; ++gx) {
            double sum = 0.0, sum2 = 0.0;
            for (const Image* image : images) {
                const double l = luminanceAt(*image, gx * step, gy * step);
                if (!std::isfinite(l)) continue;
                sum += l;
                sum2 += l * l;
            }
            const double n = double(images.size());
            const double variance = std::max(0.0, sum2 / n - (sum / n) * (sum / n));
            at(gx + 1, gy + 1) = variance + at(gx, gy + 1) + at(gx + 1, gy) - at(gx, gy);
        }
    // The window (in grid cells) with the largest sum.
    const int ww = std::min(gw, std::max(1, side / step)),
              wh = std::min(gh, std::max(1, side / step));
    double best = -1.0;
    int bx = 0, by = 0;
    for (int y = 0; y + wh <= gh; ++y)
        for (int x = 0; x + ww <= gw; ++x) {
            const double sum = at(x + ww, y + wh) - at(x, y + wh) - at(x + ww, y) + at(x, y);
            if (sum > best) {
                best = sum;
                bx = x;
                by = y;
            }
        }
    Rect r;
    r.x0 = std::min(bx * step, std::max(0, first.width() - side));
    r.y0 = std::min(by * step, std::max(0, first.height() - side));
    r.x1 = std::min(first.width(), r.x0 + side);
    r.y1 = std::min(first.height(), r.y0 + side);
    return r;
}

}  // namespace glint::studio
