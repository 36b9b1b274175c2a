// The region of interest of the workflow: a free-form lasso polygon in image pixels, or the whole
// image (the default). Filters preview and the bank builds over its bounding rectangle; fills use
// its mask. No widgets here.
#pragma once

#include <QObject>
#include <QPointF>
#include <QString>
#include <QVector>

#include <optional>
#include <vector>

#include "glint/image/image.h"

namespace glint::studio {

class RegionOfInterest : public QObject {
    Q_OBJECT
  public:
    explicit RegionOfInterest(QObject* parent = nullptr) : QObject(parent) {}

    /// A lasso (at least 3 points, image pixels); fewer points mean the whole image.
    void setPolygon(const QVector<QPointF>& polygon);
    /// The whole image.
    void clear();
    bool wholeImage() const { return m_polygon.isEmpty(); }
    const QVector<QPointF>& polygon() const { return m_polygon; }

    /// The pixels the region touches, clipped to a width × height image (the whole image when
    /// the region is, or when the lasso lies outside).
    Rect bounds(int width, int height) const;
    /// 1 inside the polygon (pixel centres, even-odd rule), 0 outside; all 1 for the whole image.
    Image mask(int width, int height) const;
    /// The pixels of the mask that are 1 (without making it).
    qint64 pixelCount(int width, int height) const;

    /// The lasso's points as x, y pairs (empty: the whole image), for the autosave journal, and
    /// back (an odd count gives the whole image).
    std::vector<double> coordinates() const;
    void setCoordinates(const std::vector<double>& xy);

    /// "x y x y ..." for a session's view state, and back (malformed text gives the whole image).
    QString toString() const;
    void fromString(const QString& text);

  signals:
    void changed();

  private:
    QVector<QPointF> m_polygon;
};

/// Rasterises `polygon` (image pixels) into a 1-channel 0/1 mask: a pixel is inside when its
/// centre is (even-odd rule). One scanline pass per row over the polygon's edges.
Image rasterizePolygon(const QVector<QPointF>& polygon, int width, int height);

}  // namespace glint::studio
