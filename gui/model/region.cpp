#include "model/region.h"

#include <QStringList>

#include <algorithm>
#include <cmath>
#include <vector>

namespace glint::studio {

namespace {

// Calls run(y, x0, x1) for each run of pixels [x0, x1) of row y whose centres `polygon` holds
// (even-odd rule): one scanline pass per row over the polygon's edges.
template <class Run>
void insideRuns(const QVector<QPointF>& polygon, int width, int height, Run run) {
    const qsizetype n = polygon.size();
    if (n < 3) return;
    std::vector<double> crossings;
    for (int y = 0; y < height; ++y) {
        // Where the polygon's edges cross the row of pixel centres.
        const double yc = y + 0.5;
        crossings.clear();
        for (qsizetype i = 0; i < n; ++i) {
            const QPointF& a = polygon[i];
            const QPointF& b = polygon[(i + 1) % n];
            if ((a.y() <= yc) == (b.y() <= yc)) continue;
            crossings.push_back(a.x() + (yc - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
        }
        std::sort(crossings.begin(), crossings.end());
        // Pixels whose centre lies between a pair of crossings are inside.
        for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
            const int x0 = std::max(0, int(std::ceil(crossings[k] - 0.5)));
            const int x1 = std::min(width, int(std::ceil(crossings[k + 1] - 0.5)));
            if (x0 < x1) run(y, x0, x1);
        }
    }
}

}  // namespace

Image rasterizePolygon(const QVector<QPointF>& polygon, int width, int height) {
    Image mask(width, height, 1, 0.0f);
    insideRuns(polygon, width, height, [&](int y, int x0, int x1) {
        for (int x = x0; x < x1; ++x) mask(x, y, 0) = 1.0f;
    });
    return mask;
}

void RegionOfInterest::setPolygon(const QVector<QPointF>& polygon) {
    m_polygon = polygon.size() >= 3 ? polygon : QVector<QPointF>{};
    emit changed();
}

void RegionOfInterest::clear() {
    m_polygon.clear();
    emit changed();
}

Rect RegionOfInterest::bounds(int width, int height) const {
    const Rect whole{0, width, 0, height};
    if (m_polygon.isEmpty()) return whole;
    double x0 = m_polygon[0].x(), x1 = x0, y0 = m_polygon[0].y(), y1 = y0;
    for (const QPointF& p : m_polygon) {
        x0 = std::min(x0, p.x());
        x1 = std::max(x1, p.x());
        y0 = std::min(y0, p.y());
        y1 = std::max(y1, p.y());
    }
    const Rect r = intersect(
        Rect{int(std::floor(x0)), int(std::ceil(x1)), int(std::floor(y0)), int(std::ceil(y1))},
        whole);
    return r.empty() ? whole : r;
}

Image RegionOfInterest::mask(int width, int height) const {
    if (m_polygon.isEmpty()) return Image(width, height, 1, 1.0f);
    return rasterizePolygon(m_polygon, width, height);
}

qint64 RegionOfInterest::pixelCount(int width, int height) const {
    if (m_polygon.isEmpty()) return qint64(width) * height;
    qint64 count = 0;
    insideRuns(m_polygon, width, height, [&](int, int x0, int x1) { count += x1 - x0; });
    return count;
}

std::vector<double> RegionOfInterest::coordinates() const {
    std::vector<double> xy;
    for (const QPointF& p : m_polygon) {
        xy.push_back(p.x());
        xy.push_back(p.y());
    }
    return xy;
}

void RegionOfInterest::setCoordinates(const std::vector<double>& xy) {
    QVector<QPointF> polygon;
    if (xy.size() % 2 == 0)
        for (std::size_t i = 0; i + 1 < xy.size(); i += 2)
            polygon.push_back(QPointF(xy[i], xy[i + 1]));
    setPolygon(polygon);
}

QString RegionOfInterest::toString() const {
    // 17 significant digits: a double comes back bit for bit, and so does the region's mask.
    QStringList parts;
    for (const QPointF& p : m_polygon)
        parts << QString::number(p.x(), 'g', 17) << QString::number(p.y(), 'g', 17);
    return parts.join(QLatin1Char(' '));
}

void RegionOfInterest::fromString(const QString& text) {
    const QStringList parts = text.split(QLatin1Char(' '), Qt::SkipEmptyParts);
    QVector<QPointF> polygon;
    bool ok = parts.size() % 2 == 0;
    for (qsizetype i = 0; ok && i + 1 < parts.size(); i += 2) {
        bool okx = false, oky = false;
        const double x = parts[i].toDouble(&okx), y = parts[i + 1].toDouble(&oky);
        ok = okx && oky && std::isfinite(x) && std::isfinite(y);
        polygon.push_back(QPointF(x, y));
    }
    setPolygon(ok ? polygon : QVector<QPointF>{});
}

}  // namespace glint::studio
