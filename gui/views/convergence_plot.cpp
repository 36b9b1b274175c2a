#include "views/convergence_plot.h"

#include <QPainter>

#include <algorithm>
#include <cmath>

namespace glint::studio {

ConvergencePlot::ConvergencePlot(QWidget* parent) : QWidget(parent) {
    setMinimumHeight(120);
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

void ConvergencePlot::paintEvent(QPaintEvent*) {
    QPainter p(this);
    p.fillRect(rect(), QColor(34, 34, 34));
    const QRectF area = QRectF(rect()).adjusted(44, 8, -8, -22);
    p.setPen(QColor(120, 120, 120));
    p.drawRect(area);
    p.drawText(QRectF(area.left(), area.bottom() + 2, area.width(), 18), Qt::AlignCenter,
               m_spp ? tr("samples per pixel (log)") : tr("seconds (log)"));
    std::vector<QPointF> data;
    for (const CurvePoint& c : m_points) {
        const double x = m_spp ? double(c.spp) : c.seconds;
        if (x > 0.0 && c.relMse > 0.0 && std::isfinite(c.relMse))
            data.emplace_back(std::log10(x), std::log10(c.relMse));
    }
    if (data.empty()) {
        p.drawText(area, Qt::AlignCenter,
                   tr("With a reference, each pass of a render\nadds a point here"));
        return;
    }
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
    auto map = [&](const QPointF& d) {
        return QPointF(area.left() + (d.x() - x0) / (x1 - x0) * area.width(),
                       area.bottom() - (d.y() - y0) / (y1 - y0) * area.height());
    };
    p.setPen(QColor(150, 150, 150));
    p.drawText(QRectF(0, area.top() - 6, 42, 14), Qt::AlignRight,
               QString::number(std::pow(10.0, y1), 'g', 2));
    p.drawText(QRectF(0, area.bottom() - 8, 42, 14), Qt::AlignRight,
               QString::number(std::pow(10.0, y0), 'g', 2));
    p.drawText(QRectF(area.left(), area.bottom() + 2, 60, 16), Qt::AlignLeft,
               QString::number(std::pow(10.0, x0), 'g', 2));
    p.drawText(QRectF(area.right() - 60, area.bottom() + 2, 60, 16), Qt::AlignRight,
               QString::number(std::pow(10.0, x1), 'g', 2));
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setPen(QPen(QColor(255, 190, 60), 2.0));
    for (std::size_t i = 1; i < data.size(); ++i) p.drawLine(map(data[i - 1]), map(data[i]));
    p.setBrush(QColor(255, 190, 60));
    for (const QPointF& d : data) p.drawEllipse(map(d), 2.5, 2.5);
}

}  // namespace glint::studio
