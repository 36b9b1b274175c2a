#include "views/canvas_overlays.h"

#include <QFontMetrics>
#include <QPainter>

#include <algorithm>
#include <cmath>

#include "glint/image/flip.h"
#include "glint/image/io.h"
#include "views/display.h"

namespace glint::studio {

namespace {

constexpr int kPlateMargin = 8;   // from the canvas's edge
constexpr int kPlatePadding = 5;  // inside the plate

void plate(QPainter& p, const QRect& r) {
    p.save();
    p.setRenderHint(QPainter::Antialiasing, true);
    p.setPen(Qt::NoPen);
    p.setBrush(QColor(20, 20, 20, 190));
    p.drawRoundedRect(r, 4, 4);
    p.restore();
}

}  // namespace

QImage flipOverlay(const Image& errors) {
    const Image colors = flipColorMap(errors);
    QImage out(colors.width(), colors.height(), QImage::Format_ARGB32_Premultiplied);
    auto byte = [](float linear) {
        return int(std::lround(std::clamp(srgbEncode(linear), 0.0f, 1.0f) * 255.0f));
    };
    for (int y = 0; y < colors.height(); ++y) {
        auto* dst = reinterpret_cast<QRgb*>(out.scanLine(y));
        for (int x = 0; x < colors.width(); ++x)
            dst[x] = qRgb(byte(colors(x, y, 0)), byte(colors(x, y, 1)), byte(colors(x, y, 2)));
    }
    return out;
}

void drawCanvasLabel(QPainter& p, const QRect& area, const QString& text) {
    if (text.isEmpty()) return;
    const QFontMetrics fm(p.font());
    const QRect box(area.left() + kPlateMargin, area.top() + kPlateMargin,
                    fm.horizontalAdvance(text) + 2 * kPlatePadding,
                    fm.height() + 2 * kPlatePadding);
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
    const QRect box(area.right() - kPlateMargin - barWidth - 2 * kPlatePadding,
                    area.bottom() - kPlateMargin - barHeight - fm.height() - 3 * kPlatePadding,
                    barWidth + 2 * kPlatePadding, barHeight + fm.height() + 3 * kPlatePadding);
    plate(p, box);
    // The ramp, one column per step.
    const QRect bar(box.left() + kPlatePadding, box.top() + kPlatePadding, barWidth, barHeight);
    for (int x = 0; x < barWidth; ++x)
        p.fillRect(QRect(bar.left() + x, bar.top(), 1, barHeight),
                   QColor(falseColor(float(x) / float(barWidth - 1))));
    p.setPen(QColor(235, 235, 235));
    const QRect text(bar.left(), bar.bottom() + kPlatePadding, barWidth, fm.height());
    p.drawText(text, Qt::AlignLeft | Qt::AlignVCenter, labels[0]);
    p.drawText(text, Qt::AlignRight | Qt::AlignVCenter, labels[1]);
}

void drawCategoryLegend(QPainter& p, const QRect& area,
                        const QList<QPair<QColor, QString>>& entries) {
    const QFontMetrics fm(p.font());
    const int swatch = fm.height() - 4, line = fm.height() + 2;
    int textWidth = 0;
    for (const auto& e : entries) textWidth = std::max(textWidth, fm.horizontalAdvance(e.second));
    const int w = swatch + 6 + textWidth + 2 * kPlatePadding;
    const int h = int(entries.size()) * line + 2 * kPlatePadding;
    const QRect box(area.left() + kPlateMargin, area.bottom() - kPlateMargin - h, w, h);
    plate(p, box);
    int y = box.top() + kPlatePadding;
    for (const auto& e : entries) {
        p.fillRect(QRect(box.left() + kPlatePadding, y + 3, swatch, swatch), e.first);
        p.setPen(QColor(235, 235, 235));
        p.drawText(QRect(box.left() + kPlatePadding + swatch + 6, y, textWidth, line),
                   Qt::AlignLeft | Qt::AlignVCenter, e.second);
        y += line;
    }
}

}  // namespace glint::studio
