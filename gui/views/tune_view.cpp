#include "views/tune_view.h"

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include "glint/denoise/registry.h"
#include "model/first_denoise.h"
#include "model/layer_names.h"

namespace glint::studio {

TuneView::TuneView(const StudioContext& context, QWidget* parent) : StageView(context, parent) {
    m_filter = new QComboBox(this);
    // Each filter by its display name (the palette's and Navigate's), its registry name the
    // item's data and tooltip.
    for (const denoise::Filter* f : denoise::allFilters()) {
        const std::string id(f->name());
        m_filter->addItem(filterTitle(id), QString::fromStdString(id));
        m_filter->setItemData(m_filter->count() - 1, QString::fromStdString(id), Qt::ToolTipRole);
    }
    m_filter->setToolTip(tr("The filter to tune"));
    m_description = new QLabel(this);
    m_description->setWordWrap(true);
    // The summary wraps to the panel's width, never sets it: the full help is its tooltip.
    m_description->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
    m_description->setMinimumWidth(0);
    m_controls = new ParamControls(this);
    m_preview = new QCheckBox(tr("Preview in the region"), this);
    m_preview->setChecked(true);
    m_state = new QLabel(this);
    m_state->setWordWrap(true);
    auto* paint = new QPushButton(tr("Paint with it"), this);
    paint->setToolTip(tr("Add the filter as a layer with weight 0 and go to the paint stage"));
    auto* apply = new QPushButton(tr("Apply to region"), this);
    apply->setToolTip(tr("Add the filter as a layer with weight 1 inside the region"));
    auto* buttons = new QHBoxLayout;
    buttons->addWidget(paint);
    buttons->addWidget(apply);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(m_filter);
    layout->addWidget(m_description);
    layout->addWidget(m_controls);
    layout->addWidget(m_preview);
    layout->addLayout(buttons);
    layout->addWidget(m_state);
    layout->addStretch(1);

    m_debounce.setSingleShot(true);
    m_debounce.setInterval(30);
    connect(&m_debounce, &QTimer::timeout, this, &TuneView::computePreview);
    connect(m_filter, &QComboBox::currentIndexChanged, this, &TuneView::filterChanged);
    connect(m_filter, &QComboBox::activated, this, [this] { m_userChose = true; });
    connect(m_controls, &ParamControls::valuesChanged, this, [this](const denoise::ParamValues& v) {
        m_userChose = true;
        m_memory[filter()] = v;
        schedulePreview();
    });
    connect(m_preview, &QCheckBox::toggled, this, [this](bool on) {
        if (on)
            schedulePreview();
        else
            m_context.viewer->canvas()->clearPreview();
    });
    connect(paint, &QPushButton::clicked, this, [this] { choose(false); });
    connect(apply, &QPushButton::clicked, this, [this] { choose(true); });
    connect(m_context.region, &RegionOfInterest::changed, this, &TuneView::schedulePreview);
    connect(m_context.session, &SessionAdapter::inputChanged, this, &TuneView::schedulePreview);
    filterChanged();
}

std::string TuneView::filter() const {
    return m_filter->currentData().toString().toStdString();
}

void TuneView::setFilter(const std::string& name) {
    m_userChose = true;
    const int i = m_filter->findData(QString::fromStdString(name));
    if (i >= 0) m_filter->setCurrentIndex(i);
}

void TuneView::setValues(const denoise::ParamValues& values) {
    m_userChose = true;
    denoise::ParamValues merged = m_controls->values();
    for (const auto& [k, v] : values) merged[k] = v;
    m_memory[filter()] = merged;
    const denoise::Filter& f = denoise::findFilter(filter());
    m_controls->setSpecs(f.params(), merged);
    schedulePreview();
}

void TuneView::filterChanged() {
    const denoise::Filter& f = denoise::findFilter(filter());
    const QString description =
        QString::fromUtf8(f.description().data(), qsizetype(f.description().size()));
    // The first paragraph on the panel; the whole (equations, parameters) in a tooltip that
    // keeps its lines, so the panel's width does not depend on the filter's help.
    QString summary = description.section(QStringLiteral("\n\n"), 0, 0);
    summary.replace(QLatin1Char('\n'), QLatin1Char(' '));
    m_description->setText(summary);
    m_description->setToolTip(QStringLiteral("<pre style=\"white-space:pre-wrap\">%1</pre>")
                                  .arg(description.toHtmlEscaped()));
    m_controls->setSpecs(f.params(), m_memory[filter()]);
    schedulePreview();
}

void TuneView::choose(bool fillRegion) {
    try {
        addChosenLayer(m_context, filter(), m_controls->values(), fillRegion);
        emit status(tr("Adding %1 as a layer…").arg(choiceName(filter(), m_controls->values())));
        emit layerChosen();
    } catch (const Error& e) {
        emit failed(tr("Cannot add the layer"), QString::fromStdString(e.what()));
    }
}

void TuneView::activate() {
    m_context.viewer->canvas()->setTool(ImageCanvas::Tool::Pan);
    startFromTheResult();
    schedulePreview();
}

void TuneView::startFromTheResult() {
    if (m_userChose || !m_context.session->hasSession()) return;
    // The top layer a filter makes (Auto's correction is none), with its parameters: the
    // preview then shows what the result shows there.
    const denoise::Session& s = m_context.session->session();
    std::string name;
    denoise::ParamValues params;
    for (std::size_t i = s.layerCount(); i-- > 0 && name.empty();)
        if (m_filter->findData(QString::fromStdString(s.layer(i).filter)) >= 0) {
            name = s.layer(i).filter;
            params = s.layer(i).params;
        }
    // No layer yet: the filter the studio prefers for a first image, at its defaults (its first
    // candidate; measuring them all runs the filters, which the UI thread does not).
    if (name.empty())
        if (FramePtr in = m_context.session->input()) {
            const std::vector<std::string> candidates = FirstDenoise::candidatesFor(*in);
            if (!candidates.empty()) name = candidates.front();
        }
    const int index = m_filter->findData(QString::fromStdString(name));
    if (index < 0) return;
    m_memory[name] = params;
    if (index == m_filter->currentIndex())
        filterChanged();
    else
        m_filter->setCurrentIndex(index);
}

void TuneView::deactivate() {
    m_tasks.cancel(QStringLiteral("preview"));
    m_context.viewer->canvas()->clearPreview();
}

void TuneView::schedulePreview() {
    m_previewReady = false;
    if (m_active && m_preview->isChecked()) m_debounce.start();
}

void TuneView::computePreview() {
    FramePtr in = m_context.session->filterInput();
    if (!in || !m_active) return;
    const Rect rect = m_context.region->bounds(in->width(), in->height());
    const denoise::Filter* f = &denoise::findFilter(filter());
    const denoise::ParamValues values = m_controls->values();
    m_state->setText(tr("Previewing…"));
    m_tasks.run<Image>(
        QStringLiteral("preview"),
        [in, f, values, rect](const TaskRunner::CancelFlag& cancel) {
            denoise::FilterOptions o;
            o.region = rect;
            o.progress = [cancel](double) { return !cancel->load(); };
            return denoise::applyFilter(*f, *in, values, o);
        },
        [this, rect](Image preview) {
            if (!m_active) return;
            m_context.viewer->canvas()->setPreview(preview, rect);
            m_state->clear();
            m_previewReady = true;
            emit previewShown();
        },
        [this](const QString& message) { m_state->setText(message); });
}

}  // namespace glint::studio
