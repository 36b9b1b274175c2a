#include "views/log_control.h"

#include <QHBoxLayout>
#include <QSignalBlocker>
#include <QSlider>

#include <algorithm>
#include <cmath>

namespace glint::studio {

namespace {
constexpr double kHalfStop = 1.4142135623730951;  // 2^(1/2)
}

void LogSpinBox::stepBy(int steps) {
    const double v = value();
    if (v <= 0.0) {
        if (steps > 0) setValue(std::max(singleStep(), minimum()));
        return;
    }
    setValue(v * std::pow(kHalfStop, steps));
}

LogControl::LogControl(double min, double max, QWidget* parent) : QWidget(parent) {
    m_slider = new QSlider(Qt::Horizontal, this);
    m_slider->setRange(-kStops * kStepsPerStop, kStops * kStepsPerStop);
    m_slider->setPageStep(kStepsPerStop);
    m_slider->setSingleStep(1);
    // Wide enough that a pixel is a small fraction of a stop.
    m_slider->setMinimumWidth(100);
    m_slider->setToolTip(tr("Drag: ±%1 stops around the value (each stop doubles it)").arg(kStops));
    m_spin = new LogSpinBox(this);
    m_spin->setRange(std::max(0.0, min), max);
    m_spin->setDecimals(3);
    m_spin->setSingleStep(0.01);
    m_spin->setKeyboardTracking(false);
    m_spin->setMinimumWidth(72);
    auto* layout = new QHBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(m_slider, 1);
    layout->addWidget(m_spin);
    connect(m_slider, &QSlider::valueChanged, this, [this](int s) {
        {
            const QSignalBlocker block(m_spin);
            m_spin->setValue(fromSlider(s));
        }
        emit valueChanged(m_spin->value());
        // A step by keys or a click beside the handle is an edit of its own.
        if (!m_slider->isSliderDown()) emit editingFinished(m_spin->value());
    });
    connect(m_slider, &QSlider::sliderReleased, this, [this] {
        emit editingFinished(value());
        recentre();
    });
    connect(m_spin, &QDoubleSpinBox::valueChanged, this, [this](double v) {
        recentre();
        emit valueChanged(v);
        emit editingFinished(v);
    });
}

double LogControl::value() const {
    return m_spin->value();
}

void LogControl::setValue(double v) {
    const QSignalBlocker block(m_spin);
    m_spin->setValue(v);
    recentre();
}

double LogControl::fromSlider(int position) const {
    const double v = m_centre * std::exp2(double(position) / kStepsPerStop);
    return std::clamp(v, m_spin->minimum(), m_spin->maximum());
}

void LogControl::recentre() {
    // Zero (a light switched off) puts the middle at 1: the slider then starts at 1/2^kStops.
    const double v = m_spin->value();
    m_centre = v > 0.0 ? v : 1.0;
    const QSignalBlocker block(m_slider);
    m_slider->setValue(v > 0.0 ? 0 : m_slider->minimum());
}

}  // namespace glint::studio
