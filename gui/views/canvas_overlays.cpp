#include "views/canvas_overlays.h"

#include <QFontMetrics>
#include <QPainter>

#include "views/display.h"

namespace glint::studio {

namespace {

constexpr int kMargin = 8;   // from the canvas's edge
constexpr int kPadding = 5;  // inside the plate

void plate(QPainter& p, const QRect& r) {
    p.save();
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setPen(Qt::NoPen);
    p.setBrush(QColor(20, 20, 20, 190));
    p.drawRoundedRect(r, 4, 4);
    p.restore();
}

}  // namespace

void drawCanvasLabel(QPainter& p, const QRect& area, const QString& text) {
    if (text.isEmpty()) return;
    const QFontMetrics fm(p.font());
    const QRect box(area.left() + kMargin, area.top() + kMargin,
                    fm.horizontalAdvance(text) + 2 * kPadding, fm.height() + 2 * kPadding);
    plate(p, box);
    p.setPen(QColor(235, 235, 235));
    p.drawText(box, Qt::AlignCenter, text);
}

QStringList legendLabels(float lo, float hi) {
    return {QString::number(double(lo), 'g', 3), QString::number(double(hi), 'g', 3)};
}

void drawFalseColorLegend(QPainter& p, const QRect& area, float lo, float hi) {
    const QFontMetrics fm(p.font());
    const QStringList labels = legendLabels(lo, hi);
    const int barWidth = 160, barHeight = 10;
    const QRect box(area.right() - kMargin - barWidth - 2 * kPadding,
                    area.bottom() - kMargin - barHeight - fm.height() - 3 * kPadding,
                    barWidth + 2 * kPadding, barHeight + fm.height() + 3 * kPadding);
    plate(p, box);
    // The ramp, one column per step.
    const QRect bar(box.left() + kPadding, box.top() + kPadding, barWidth, barHeight);
    for (int x = 0; x < barWidth; ++x)
        p.fillRect(QRect(bar.left() + x, bar.top(), 1, barHeight),
                   QColor(falseColor(float(x) / float(barWidth - 1))));
    p.setPen(QColor(235, 235, 235));
    const QRect text(bar.left(), bar.bottom() + kPadding, barWidth, fm.height());
    p.drawText(text, Qt::AlignLeft | Qt::AlignVCenter, labels[0]);
    p.drawText(text, Qt::AlignRight | Qt::AlignVCenter, labels[1]);
}

}  // namespace glint::studio
