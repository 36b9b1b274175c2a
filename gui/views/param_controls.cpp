#include "views/param_controls.h"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSlider>

#include <algorithm>
#include <cmath>

#include "glint/denoise/registry.h"

namespace glint::studio {

namespace {
constexpr int kSliderSteps = 1000;
}

QString describeFilter(const std::string& filter, const denoise::ParamValues& params) {
    const std::string values = denoise::paramsSummary(denoise::findFilter(filter).params(), params);
    return QString::fromStdString(values.empty() ? filter : filter + " " + values);
}

ScalarControl::ScalarControl(double min, double max, double sliderMin, double sliderMax,
                             bool logScale, bool integer, QWidget* parent)
    : QWidget(parent),
      m_sliderMin(sliderMin),
      m_sliderMax(std::max(sliderMax, sliderMin)),
      m_log(logScale && sliderMin > 0.0),
      m_integer(integer) {
    m_slider = new QSlider(Qt::Horizontal, this);
    m_slider->setRange(0, kSliderSteps);
    m_spin = new QDoubleSpinBox(this);
    m_spin->setRange(min, max);
    // Enough decimals for the smallest useful step of the range.
    const double span = std::max(std::abs(sliderMax), std::abs(sliderMin));
    m_spin->setDecimals(integer ? 0 : span >= 100.0 ? 1 : (m_log && sliderMin < 0.01) ? 5 : 3);
    m_spin->setSingleStep(integer ? 1.0 : (m_sliderMax - m_sliderMin) / 100.0);
    m_spin->setKeyboardTracking(false);
    m_spin->setMinimumWidth(64);
    m_slider->setMinimumWidth(60);
    auto* layout = new QHBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(m_slider, 1);
    layout->addWidget(m_spin);
    connect(m_slider, &QSlider::valueChanged, this, [this](int s) {
        double v = fromSlider(s);
        if (m_integer) v = std::round(v);
        m_spin->blockSignals(true);
        m_spin->setValue(v);
        m_spin->blockSignals(false);
        emit valueChanged(m_spin->value());
    });
    connect(m_slider, &QSlider::sliderReleased, this, [this] { emit editingFinished(value()); });
    connect(m_spin, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        m_slider->blockSignals(true);
        m_slider->setValue(toSlider(v));
        m_slider->blockSignals(false);
        emit valueChanged(v);
        emit editingFinished(v);
    });
}

double ScalarControl::value() const {
    return m_spin->value();
}

void ScalarControl::setValue(double v) {
    m_spin->blockSignals(true);
    m_slider->blockSignals(true);
    m_spin->setValue(v);
    m_slider->setValue(toSlider(v));
    m_spin->blockSignals(false);
    m_slider->blockSignals(false);
}

int ScalarControl::toSlider(double v) const {
    double t = 0.0;
    if (m_sliderMax <= m_sliderMin) return 0;
    if (m_log)
        t = std::log(std::max(v, m_sliderMin) / m_sliderMin) / std::log(m_sliderMax / m_sliderMin);
    else
        t = (v - m_sliderMin) / (m_sliderMax - m_sliderMin);
    return int(std::lround(std::clamp(t, 0.0, 1.0) * kSliderSteps));
}

double ScalarControl::fromSlider(int s) const {
    const double t = double(s) / kSliderSteps;
    if (m_log) return m_sliderMin * std::pow(m_sliderMax / m_sliderMin, t);
    return m_sliderMin + t * (m_sliderMax - m_sliderMin);
}

ParamControls::ParamControls(QWidget* parent) : QWidget(parent) {
    m_form = new QFormLayout(this);
    m_form->setContentsMargins(0, 0, 0, 0);
    m_form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
    // A long label ("depth sigma (relative)") puts its control on the next row rather than
    // widening the panel: the panel's width does not depend on the filter chosen.
    m_form->setRowWrapPolicy(QFormLayout::WrapLongRows);
}

void ParamControls::setSpecs(const std::vector<denoise::ParamSpec>& specs,
                             const denoise::ParamValues& values) {
    while (m_form->rowCount() > 0) m_form->removeRow(0);
    m_specs = specs;
    m_values.clear();
    for (const denoise::ParamSpec& spec : specs) {
        auto it = values.find(spec.name);
        const double v = it != values.end() ? it->second : spec.defaultValue;
        m_values[spec.name] = v;
        QWidget* control = nullptr;
        if (spec.isChoice()) {
            auto* box = new QComboBox(this);
            for (const std::string& c : spec.choices) box->addItem(QString::fromStdString(c));
            box->setCurrentIndex(int(v));
            connect(box, &QComboBox::currentIndexChanged, this, [this, name = spec.name](int i) {
                m_values[name] = i;
                emit valuesChanged(m_values);
            });
            control = box;
        } else {
            auto* scalar =
                new ScalarControl(spec.min, spec.max, spec.softMin, spec.softMax,
                                  spec.scale == denoise::ParamScale::Log, spec.integer, this);
            scalar->setValue(v);
            connect(scalar, &ScalarControl::valueChanged, this, [this, name = spec.name](double x) {
                m_values[name] = x;
                emit valuesChanged(m_values);
            });
            control = scalar;
        }
        control->setObjectName(QString::fromStdString(spec.name));
        control->setToolTip(QString::fromStdString(spec.help));
        auto* label = new QLabel(QString::fromStdString(spec.label), this);
        label->setToolTip(QString::fromStdString(spec.help));
        label->setWordWrap(true);
        m_form->addRow(label, control);
    }
}

}  // namespace glint::studio
