// Controls generated from descriptions: a slider with a spin box per numeric ParamSpec (log
// sliders where the scale is log, the soft range on the slider and the full range in the box),
// a combo box per choice, tooltips from the help text. Used by the tune stage and the feature
// prefilter; ScalarControl is also what the look panel uses.
#pragma once

#include <QWidget>

#include <vector>

#include "glint/denoise/filter.h"

class QSlider;
class QDoubleSpinBox;
class QComboBox;
class QFormLayout;

namespace glint::studio {

/// "bilateral sigmaS=2 sigmaR=0.1": a filter and its parameters as the filter formats them.
QString describeFilter(const std::string& filter, const denoise::ParamValues& params);

/// One number: a slider over [sliderMin, sliderMax] (linear or log) and a spin box over
/// [min, max].
class ScalarControl : public QWidget {
    Q_OBJECT
  public:
    ScalarControl(double min, double max, double sliderMin, double sliderMax, bool logScale,
                  bool integer, QWidget* parent = nullptr);
    double value() const;
    /// Sets the value without emitting valueChanged.
    void setValue(double value);

  signals:
    /// The user changed the value (while dragging, too).
    void valueChanged(double value);
    /// The user let go of the slider or finished typing.
    void editingFinished(double value);

  private:
    int toSlider(double v) const;
    double fromSlider(int s) const;

    QSlider* m_slider;
    QDoubleSpinBox* m_spin;
    double m_sliderMin, m_sliderMax;
    bool m_log;
    bool m_integer;
};

/// A form of controls for a list of ParamSpecs.
class ParamControls : public QWidget {
    Q_OBJECT
  public:
    explicit ParamControls(QWidget* parent = nullptr);
    /// Rebuilds the form for `specs` with `values` (missing names take their defaults).
    void setSpecs(const std::vector<denoise::ParamSpec>& specs, const denoise::ParamValues& values);
    denoise::ParamValues values() const { return m_values; }

  signals:
    void valuesChanged(const denoise::ParamValues& values);

  private:
    QFormLayout* m_form;
    std::vector<denoise::ParamSpec> m_specs;
    denoise::ParamValues m_values;
};

}  // namespace glint::studio
