// A small log-log plot of relMSE against seconds (or samples per pixel) while a render refines:
// the curve pbrt-v4 writes to a file, drawn live.
#pragma once

#include <QWidget>

#include <vector>

#include "model/document.h"

namespace glint::studio {

class ConvergencePlot : public QWidget {
    Q_OBJECT
  public:
    explicit ConvergencePlot(QWidget* parent = nullptr);
    void setPoints(const std::vector<CurvePoint>& points);
    /// The x axis: seconds (default) or samples per pixel.
    void setAgainstSpp(bool spp);
    QSize sizeHint() const override { return {280, 150}; }

    /// Where the plot's texts go at its present size and data (the axis title, the tick
    /// labels): laid out from the font, each inside the widget and clear of the others.
    struct Texts {
        QRectF area;  ///< the plotting frame
        std::vector<std::pair<QRectF, QString>> items;
    };
    Texts texts() const;

  protected:
    void paintEvent(QPaintEvent* event) override;

  private:
    /// The data in log-log coordinates and its ranges (x0, x1, y0, y1; at least a decade).
    std::vector<QPointF> logData(double range[4]) const;
    std::vector<CurvePoint> m_points;
    bool m_spp = false;
};

}  // namespace glint::studio
