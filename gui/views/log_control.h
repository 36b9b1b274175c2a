// A strength or an exposure: a quantity that matters by its ratios. The slider moves in stops
// (factors of two) around the value, a few stops either way, so a short drag is a small change
// at any magnitude (a linear or decades-wide slider made 19 px go from 1 to 396); it re-centres
// on the value when released, so longer changes are several drags. The spin box takes any value
// of the full range, and its arrows step by half a stop.
#pragma once

#include <QDoubleSpinBox>
#include <QWidget>

class QSlider;

namespace glint::studio {

/// A spin box whose steps multiply the value (by 2^(1/2) per step); from zero the first step up
/// goes to its smallest positive step.
class LogSpinBox : public QDoubleSpinBox {
    Q_OBJECT
  public:
    using QDoubleSpinBox::QDoubleSpinBox;
    void stepBy(int steps) override;
};

class LogControl : public QWidget {
    Q_OBJECT
  public:
    /// Stops either side of the value the slider spans, and slider steps per stop.
    static constexpr int kStops = 4;
    static constexpr int kStepsPerStop = 8;

    /// A control over [min, max] (min ≥ 0).
    LogControl(double min, double max, QWidget* parent = nullptr);
    double value() const;
    /// Sets the value (the slider centred on it) without emitting valueChanged.
    void setValue(double value);
    QSlider* slider() const { return m_slider; }
    QDoubleSpinBox* spinBox() const { return m_spin; }

  signals:
    /// The user changed the value (while dragging, too).
    void valueChanged(double value);
    /// The user let go of the slider, stepped it or finished typing.
    void editingFinished(double value);

  private:
    double fromSlider(int position) const;
    void recentre();

    QSlider* m_slider;
    LogSpinBox* m_spin;
    double m_centre = 1.0;  // the value at the slider's middle
};

}  // namespace glint::studio
