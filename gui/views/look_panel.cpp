#include "views/look_panel.h"

#include <QColorDialog>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QScrollArea>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <memory>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "model/look_command.h"
#include "views/log_control.h"
#include "views/param_controls.h"

namespace glint::studio {

namespace {

// The swatch colour of a linear RGB value, sRGB-encoded. A value brighter than 1 (a light's
// radiance) is divided by its largest component: the swatch shows its hue, not white. Dividing
// by the property's range instead turned every environment colour black (the range is 1e18).
QColor swatchColor(const std::array<double, 3>& v) {
    const double peak = std::max({v[0], v[1], v[2]});
    const double scale = peak > 1.0 ? 1.0 / peak : 1.0;
    auto c = [&](double x) {
        return int(std::lround(255.0 * srgbEncode(float(std::clamp(x * scale, 0.0, 1.0)))));
    };
    return QColor(c(v[0]), c(v[1]), c(v[2]));
}

// The slider's range for a linear scalar: bounded even when the property's range is not (a
// rotation ±1e6), so a short drag stays a small change; the spin box beside it takes any value of
// the full range. (Strengths, logarithmic, have a LogControl.)
std::pair<double, double> sliderRange(const render::LookProperty& p) {
    if (p.max - p.min > 1e4) return {std::max(p.min, -360.0), std::min(p.max, 360.0)};
    return {p.min, p.max};
}

void paintSwatch(QPushButton* button, const QColor& color) {
    button->setStyleSheet(
        QStringLiteral("background-color: %1; border: 1px solid #222;").arg(color.name()));
}

constexpr double kAnyValue = 1e9;

std::string keyOf(const render::LookItem& item, const render::LookProperty& p) {
    return item.name + "/" + p.name;
}

}  // namespace

LookPanel::LookPanel(Document* document, SessionAdapter* session, QWidget* parent)
    : QWidget(parent), m_document(document), m_session(session) {
    m_scroll = new QScrollArea(this);
    m_scroll->setWidgetResizable(true);
    m_scroll->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->addWidget(m_scroll);
    connect(m_document, &Document::lookChanged, this, [this] {
        // Rebuild when the items changed (another scene), else only refresh the values.
        std::vector<std::string> keys;
        for (const auto& item : m_document->look())
            for (const auto& p : item.properties) keys.push_back(keyOf(item, p));
        if (keys != m_builtFor)
            rebuild();
        else
            refreshValues();
    });
    rebuild();
}

void LookPanel::edit(const std::string& item, const std::string& property,
                     const std::array<double, 3>& value) {
    try {
        const std::array<double, 3> before = m_document->lookValue(item, property);
        if (before == value) return;
        // push() runs the command's redo first, which throws for a refused value before the
        // stack changes: the command is then ours to delete (LeakSanitizer caught it leaking).
        auto command =
            std::make_unique<LookCommand>(m_document, m_session, item, property, before, value);
        m_session->undoStack()->push(command.get());
        command.release();
    } catch (const Error& e) {
        emit failed(tr("The scene refused the change"), QString::fromStdString(e.what()));
        refreshValues();
    }
}

void LookPanel::rebuild() {
    m_builtFor.clear();
    m_content = new QWidget;
    auto* layout = new QVBoxLayout(m_content);
    if (m_document->look().empty()) {
        auto* label = new QLabel(m_document->kind() == Document::Kind::Exr
                                     ? tr("An EXR has no look to edit: open a scene.json to "
                                          "change materials and lights.")
                                     : tr("Open a scene to edit its materials and lights."));
        label->setWordWrap(true);
        layout->addWidget(label);
    }
    for (const render::LookItem& item : m_document->look()) {
        const QString title = QStringLiteral("%1%2 (%3)")
                                  .arg(QString::fromStdString(item.name),
                                       item.light ? QStringLiteral(" ✶") : QString(),
                                       QString::fromStdString(item.type));
        auto* box = new QGroupBox(title, m_content);
        auto* form = new QFormLayout(box);
        // A label and its control share a row while they fit the dock, else the control goes
        // below its label: the panel never needs a horizontal scroll bar.
        form->setRowWrapPolicy(QFormLayout::WrapLongRows);
        for (const render::LookProperty& p : item.properties) {
            QWidget* control = p.isColour ? colorControl(item, p) : scalarControl(item, p);
            control->setObjectName(QString::fromStdString(keyOf(item, p)));
            control->setToolTip(QString::fromStdString(p.help));
            auto* label = new QLabel(QString::fromStdString(p.label), box);
            label->setToolTip(QString::fromStdString(p.help));
            form->addRow(label, control);
            m_builtFor.push_back(keyOf(item, p));
        }
        layout->addWidget(box);
    }
    layout->addStretch(1);
    m_scroll->setWidget(m_content);
}

QWidget* LookPanel::colorControl(const render::LookItem& item, const render::LookProperty& p) {
    auto* w = new QWidget;
    auto* row = new QHBoxLayout(w);
    row->setContentsMargins(0, 0, 0, 0);
    auto* swatch = new QPushButton(w);
    swatch->setObjectName(QStringLiteral("swatch"));
    swatch->setFixedSize(28, 20);
    paintSwatch(swatch, swatchColor(p.value));
    row->addWidget(swatch);
    std::array<QDoubleSpinBox*, 3> spins{};
    for (int c = 0; c < 3; ++c) {
        auto* spin = new QDoubleSpinBox(w);
        // Any number can be typed: one outside the property's range is refused by the scene
        // with a message (a spin box clamped to the range refused it without a word).
        spin->setRange(-kAnyValue, std::max(p.max, kAnyValue));
        spin->setToolTip(tr("%1 to %2").arg(p.min).arg(p.max));
        spin->setDecimals(3);
        spin->setSingleStep(p.max > 1.0 ? 0.5 : 0.05);
        spin->setKeyboardTracking(false);
        spin->setValue(p.value[std::size_t(c)]);
        spin->setObjectName(QStringLiteral("c%1").arg(c));
        spin->setButtonSymbols(QAbstractSpinBox::NoButtons);
        spin->setMaximumWidth(58);
        spins[std::size_t(c)] = spin;
        row->addWidget(spin);
    }
    const std::string name = item.name, property = p.name;
    // A field shows 3 decimals and holds its value rounded to them: an edit changes its own
    // channel and keeps the others at the look's full precision (0.12345 stayed 0.123).
    for (int c = 0; c < 3; ++c)
        connect(spins[std::size_t(c)], &QDoubleSpinBox::valueChanged, this,
                [this, c, name, property](double v) {
                    std::array<double, 3> value = m_document->lookValue(name, property);
                    value[std::size_t(c)] = v;
                    edit(name, property, value);
                });
    const double max = p.max;
    connect(swatch, &QPushButton::clicked, this, [this, name, property, max] {
        // Colours up to 1 are picked directly; brighter ones (emission) keep their scale.
        const std::array<double, 3> v = m_document->lookValue(name, property);
        const double scale = max > 1.0 ? std::max({v[0], v[1], v[2], 1e-6}) : 1.0;
        const QColor picked =
            QColorDialog::getColor(swatchColor({v[0] / scale, v[1] / scale, v[2] / scale}), this);
        if (!picked.isValid()) return;
        auto lin = [&](int c) { return double(srgbDecode(float(c) / 255.0f)) * scale; };
        edit(name, property, {lin(picked.red()), lin(picked.green()), lin(picked.blue())});
    });
    return w;
}

QWidget* LookPanel::scalarControl(const render::LookItem& item, const render::LookProperty& p) {
    const std::string name = item.name, property = p.name;
    if (p.scale == ParamScale::Log) {
        // A strength: its slider moves in stops around the value (views/log_control.h).
        auto* control = new LogControl(p.min, p.max);
        control->setValue(p.value[0]);
        connect(control, &LogControl::editingFinished, this, [this, name, property](double v) {
            edit(name, property, {v, 0.0, 0.0});
        });
        return control;
    }
    const auto [sliderMin, sliderMax] = sliderRange(p);
    auto* control =
        new ScalarControl(p.min, p.max, sliderMin, sliderMax, p.scale == ParamScale::Log, false);
    control->setValue(p.value[0]);
    connect(control, &ScalarControl::editingFinished, this, [this, name, property](double v) {
        edit(name, property, {v, 0.0, 0.0});
    });
    return control;
}

void LookPanel::refreshValues() {
    if (!m_content) return;
    for (const render::LookItem& item : m_document->look())
        for (const render::LookProperty& p : item.properties) {
            QWidget* w = m_content->findChild<QWidget*>(QString::fromStdString(keyOf(item, p)));
            if (!w) continue;
            if (auto* scalar = qobject_cast<ScalarControl*>(w)) {
                scalar->setValue(p.value[0]);
                continue;
            }
            if (auto* strength = qobject_cast<LogControl*>(w)) {
                strength->setValue(p.value[0]);
                continue;
            }
            for (int c = 0; c < 3; ++c)
                if (auto* spin = w->findChild<QDoubleSpinBox*>(QStringLiteral("c%1").arg(c))) {
                    spin->blockSignals(true);
                    spin->setValue(p.value[std::size_t(c)]);
                    spin->blockSignals(false);
                }
            if (auto* swatch = w->findChild<QPushButton*>(QStringLiteral("swatch")))
                paintSwatch(swatch, swatchColor(p.value));
        }
}

}  // namespace glint::studio
