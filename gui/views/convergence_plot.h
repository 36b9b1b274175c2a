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

  protected:
    void paintEvent(QPaintEvent* event) override;

  private:
    std::vector<CurvePoint> m_points;
    bool m_spp = false;
};

}  // namespace glint::studio
