// What the canvas draws over the image, in widget coordinates: the label saying what is shown
// (top left), the false-colour legend with its range (bottom right) and a categorical map's
// legend (bottom left), all on a translucent
// dark plate that stays readable over any image; and the FLIP map as an image-sized overlay.
#pragma once

#include <QColor>
#include <QImage>
#include <QList>
#include <QPair>
#include <QRect>
#include <QString>
#include <QStringList>

#include "glint/image/image.h"

class QPainter;

namespace glint::studio {

/// A FLIP error map (1 channel in [0, 1], glint/image/flip.h) in the papers' magma colours, opaque.
QImage flipOverlay(const Image& errors);

/// Draws `text` in the top-left corner of `area`.
void drawCanvasLabel(QPainter& p, const QRect& area, const QString& text);
/// The numbers the legend writes at its ends: the range's low and high values.
QStringList legendLabels(float lo, float hi);
/// Draws the false-colour bar from `lo` (left) to `hi` (right) in the bottom-right corner of
/// `area`, with legendLabels under its ends.
void drawFalseColorLegend(QPainter& p, const QRect& area, float lo, float hi);
/// Draws a categorical map's legend (a swatch and a name a line) in the bottom-left corner of
/// `area`.
void drawCategoryLegend(QPainter& p, const QRect& area,
                        const QList<QPair<QColor, QString>>& entries);

}  // namespace glint::studio
