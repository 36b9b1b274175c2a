#include "views/convergence_plot.h"

#include <QFontMetricsF>
#include <QPainter>

#include <algorithm>
#include <cmath>

namespace glint::studio {

ConvergencePlot::ConvergencePlot(QWidget* parent) : QWidget(parent) {
    // Room for the frame and three text rows at the panel's font.
    setMinimumHeight(std::max(100, 6 * fontMetrics().height()));
    setToolTip(tr("relMSE of each pass against the reference (log-log)"));
}

void ConvergencePlot::setPoints(const std::vector<CurvePoint>& points) {
    m_points = points;
    update();
}

void ConvergencePlot::setAgainstSpp(bool spp) {
    m_spp = spp;
    update();
}

std::vector<QPointF> ConvergencePlot::logData(double range[4]) const {
    std::vector<QPointF> data;
    for (const CurvePoint& c : m_points) {
        const double x = m_spp ? double(c.spp) : c.seconds;
        if (x > 0.0 && c.relMse > 0.0 && std::isfinite(c.relMse))
            data.emplace_back(std::log10(x), std::log10(c.relMse));
    }
    if (data.empty()) return data;
    double x0 = data[0].x(), x1 = x0, y0 = data[0].y(), y1 = y0;
    for (const QPointF& d : data) {
        x0 = std::min(x0, d.x());
        x1 = std::max(x1, d.x());
        y0 = std::min(y0, d.y());
        y1 = std::max(y1, d.y());
    }
    // At least one decade on each axis, so two points do not fill the plot.
    if (x1 - x0 < 1.0) x1 = x0 + 1.0;
    if (y1 - y0 < 1.0) y0 = y1 - 1.0;
    range[0] = x0;
    range[1] = x1;
    range[2] = y0;
    range[3] = y1;
    return data;
}

ConvergencePlot::Texts ConvergencePlot::texts() const {
    // Two text rows under the frame (tick labels, then the axis title) and a column left of it
    // as wide as the widest value label, all from the font: nothing clipped or overlapping at
    // any panel width.
    const QFontMetricsF fm(font());
    const double line = fm.height();
    const double pad = 3.0;
    double range[4] = {0, 1, 0, 1};
    const std::vector<QPointF> data = logData(range);
    auto label = [](double log) { return QString::number(std::pow(10.0, log), 'g', 2); };
    const QString yTop = label(range[3]), yBottom = label(range[2]);
    const double left = std::max({fm.horizontalAdvance(QStringLiteral("8.8e-05")),
                                  fm.horizontalAdvance(yTop), fm.horizontalAdvance(yBottom)}) +
                        2 * pad;
    Texts t;
    t.area = QRectF(rect()).adjusted(left, line / 2 + pad, -pad - 4, -(2 * line + 2 * pad));
    const QRectF& a = t.area;
    const QString title = m_spp ? tr("samples per pixel (log)") : tr("seconds (log)");
    const double titleWidth = std::min(fm.horizontalAdvance(title), double(width()) - 2 * pad);
    t.items.emplace_back(
        QRectF((width() - titleWidth) / 2, a.bottom() + pad + line, titleWidth, line),
        fm.elidedText(title, Qt::ElideRight, titleWidth));
    if (data.empty()) return t;
    t.items.emplace_back(QRectF(pad, a.top() - line / 2, left - 2 * pad, line), yTop);
    t.items.emplace_back(QRectF(pad, a.bottom() - line / 2, left - 2 * pad, line), yBottom);
    const QString xMin = label(range[0]), xMax = label(range[1]);
    t.items.emplace_back(QRectF(a.left(), a.bottom() + pad, fm.horizontalAdvance(xMin), line),
                         xMin);
    const double w = fm.horizontalAdvance(xMax);
    t.items.emplace_back(QRectF(a.right() - w, a.bottom() + pad, w, line), xMax);
    return t;
}

void ConvergencePlot::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), QColor(34, 34, 34));
    const Texts t = texts();
    const QRectF& area = t.area;
    p.setPen(QColor(120, 120, 120));
    p.drawRect(area);
    double range[4] = {0, 1, 0, 1};
    const std::vector<QPointF> data = logData(range);
    if (data.empty()) {
        p.drawText(t.items[0].first, Qt::AlignCenter, t.items[0].second);
        p.drawText(area, Qt::AlignCenter,
                   tr("With a reference, each pass of a render\nadds a point here"));
        return;
    }
    p.setPen(QColor(150, 150, 150));
    for (std::size_t i = 0; i < t.items.size(); ++i) {
        // The value labels of the y axis are right-aligned against the frame.
        const bool yLabel = i == 1 || i == 2;
        p.drawText(t.items[i].first, (yLabel ? Qt::AlignRight : Qt::AlignLeft) | Qt::AlignVCenter,
                   t.items[i].second);
    }
    const double x0 = range[0], x1 = range[1], y0 = range[2], y1 = range[3];
    auto map = [&](const QPointF& d) {
        return QPointF(area.left() + (d.x() - x0) / (x1 - x0) * area.width(),
                       area.bottom() - (d.y() - y0) / (y1 - y0) * area.height());
    };
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setPen(QPen(QColor(255, 190, 60), 2.0));
    for (std::size_t i = 1; i < data.size(); ++i) p.drawLine(map(data[i - 1]), map(data[i]));
    p.setBrush(QColor(255, 190, 60));
    for (const QPointF& d : data) p.drawEllipse(map(d), 2.5, 2.5);
}

}  // namespace glint::studio
