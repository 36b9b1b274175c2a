#include "views/render_bar.h"

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QToolButton>

#include "glint/image/error.h"
#include "model/render_eta.h"

namespace glint::studio {

RenderBar::RenderBar(Document* document, ImageCanvas* canvas, QWidget* parent)
    : QWidget(parent), m_document(document), m_canvas(canvas) {
    m_spp = new QSpinBox(this);
    m_spp->setRange(1, 1 << 16);
    m_spp->setValue(16);
    m_spp->setPrefix(tr("spp "));
    m_spp->setToolTip(tr("Samples per pixel of a render: low for a quick look"));
    m_seed = new QSpinBox(this);
    m_seed->setRange(0, 1 << 30);
    m_seed->setValue(1);
    m_seed->setPrefix(tr("seed "));
    m_seed->setToolTip(tr("Seed of every per-pixel random stream (same seed, same image)"));
    m_integrator = new QComboBox(this);
    m_integrator->addItem(tr("Path tracing"), int(render::Integrator::Path));
    m_integrator->addItem(tr("Metropolis"), int(render::Integrator::Mlt));
    m_integrator->setToolTip(tr("Light transport: path tracing, or primary-sample-space MLT"));
    m_mis = new QComboBox(this);
    m_mis->addItem(tr("MIS power"), int(render::MisHeuristic::Power));
    m_mis->addItem(tr("MIS balance"), int(render::MisHeuristic::Balance));
    m_mis->addItem(tr("No MIS"), int(render::MisHeuristic::None));
    m_mis->setToolTip(tr("How light sampling and BSDF sampling are combined"));
    m_halves = new QCheckBox(tr("Halves"), this);
    m_halves->setChecked(true);
    m_halves->setToolTip(
        tr("Render two independent halves of the samples (half buffers, on by default): Auto "
           "Start then estimates each filter's error by cross-validation, which chooses much "
           "better, and Keep Refining goes on from the render. The undenoised render is "
           "somewhat noisier at equal spp. Path tracing only"));
    m_render = new QPushButton(tr("Render"), this);
    m_render->setToolTip(tr("Render with these settings (Ctrl+R)"));
    m_pause = new QPushButton(tr("Pause"), this);
    m_pause->setCheckable(true);
    m_pause->setToolTip(tr("Pause the render between tiles; press again to resume"));
    m_cancel = new QPushButton(tr("Cancel"), this);
    m_cancel->setToolTip(tr("Stop the render and keep what it has (Esc)"));
    m_regionTool = new QToolButton(this);
    m_regionTool->setText(tr("Region"));
    m_regionTool->setCheckable(true);
    m_regionTool->setToolTip(
        tr("Drag one rectangle on the image: only that part is re-rendered (the tool then "
           "disarms)"));
    m_clearRegion = new QToolButton(this);
    m_clearRegion->setText(tr("Full frame"));
    m_clearRegion->setToolTip(tr("Render the whole frame again"));
    m_progress = new QProgressBar(this);
    m_progress->setRange(0, 1000);
    m_progress->setTextVisible(false);
    m_progress->setMaximumWidth(180);
    m_progress->setMinimumWidth(60);
    m_info = new QLabel(this);
    m_info->setMinimumWidth(120);
    m_remaining = new QLabel(this);
    m_remaining->setObjectName(QStringLiteral("remaining"));
    m_remaining->setToolTip(tr("Time left, from the work done so far (pauses not counted)"));

    // Never narrower than their longest item: a narrow window cuts nothing of the names.
    m_integrator->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    m_mis->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    auto* layout = new QHBoxLayout(this);
    layout->setContentsMargins(4, 2, 4, 2);
    for (QWidget* w : std::initializer_list<QWidget*>{
             m_spp, m_seed, m_integrator, m_mis, m_halves, m_render, m_pause, m_cancel,
             m_regionTool, m_clearRegion, m_progress, m_info, m_remaining})
        layout->addWidget(w);
    layout->addStretch(1);

    connect(m_render, &QPushButton::clicked, this, [this] {
        try {
            applySettings();
            m_document->render();
        } catch (const Error& e) {
            emit failed(tr("Cannot render"), QString::fromStdString(e.what()));
        }
    });
    connect(m_pause, &QPushButton::toggled, this, [this](bool on) {
        m_document->setPaused(on);
        m_pause->setText(on ? tr("Resume") : tr("Pause"));
    });
    connect(m_cancel, &QPushButton::clicked, m_document, &Document::cancelRender);
    connect(m_integrator, &QComboBox::currentIndexChanged, this, &RenderBar::updateState);
    connect(m_spp, &QSpinBox::valueChanged, this, &RenderBar::controlChanged);
    connect(m_seed, &QSpinBox::valueChanged, this, &RenderBar::controlChanged);
    connect(m_integrator, &QComboBox::currentIndexChanged, this, &RenderBar::controlChanged);
    connect(m_mis, &QComboBox::currentIndexChanged, this, &RenderBar::controlChanged);
    connect(m_halves, &QCheckBox::toggled, this, &RenderBar::controlChanged);
    connect(m_document, &Document::settingsChanged, this, &RenderBar::showSettings);
    connect(m_regionTool, &QToolButton::toggled, this, &RenderBar::regionToolToggled);
    connect(m_clearRegion, &QToolButton::clicked, this, [this] {
        try {
            applySettings();
            m_document->render();
        } catch (const Error& e) {
            emit failed(tr("Cannot render"), QString::fromStdString(e.what()));
        }
    });
    connect(m_canvas, &ImageCanvas::renderRegionDrawn, this, [this](const QRect& r) {
        if (!m_regionTool->isChecked()) return;
        // One rectangle per arming: the next drag is the stage's again.
        disarmRegionTool();
        try {
            applySettings();
            m_document->renderRegion(Rect{r.left(), r.right() + 1, r.top(), r.bottom() + 1});
        } catch (const Error& e) {
            emit failed(tr("Cannot render"), QString::fromStdString(e.what()));
        }
    });
    connect(m_document, &Document::opened, this, &RenderBar::syncFromDocument);
    connect(m_document, &Document::renderingChanged, this, [this](bool on) {
        if (on) {
            m_rendered = true;
            m_progress->setValue(0);  // a new render starts from nothing
            m_eta.reset();
        }
        updateState();
    });
    connect(m_document, &Document::renderProgress, this,
            [this](int pass, double fraction, int spp, double seconds) {
                m_progress->setValue(int(fraction * 1000.0));
                m_info->setText(
                    tr("pass %1 · %2 spp · %3 s").arg(pass + 1).arg(spp).arg(seconds, 0, 'f', 2));
                // `pass` passes are done: the estimate starts after the first.
                const std::optional<double> left = m_eta.update(pass, fraction, seconds);
                m_remaining->setText(left ? formatRemaining(*left) : QString());
            });
    connect(m_document, &Document::frameChanged, this, [this](bool final) {
        if (!final) return;
        m_remaining->clear();
        if (!m_rendered || m_document->kind() != Document::Kind::Scene) {
            // A frame from a file, a session or a restore: no render of ours to report.
            m_progress->setValue(0);
            m_info->clear();
            return;
        }
        // A render that keeps refining past its spp reports again when it ends.
        m_rendered = m_document->refining();
        const render::RenderStats& s = m_document->lastStats();
        // A cancelled render keeps the bar where it stopped.
        if (!s.cancelled) m_progress->setValue(1000);
        m_info->setText(tr("%1 spp in %2 s%3")
                            .arg(s.completedSpp)
                            .arg(s.seconds, 0, 'f', 2)
                            .arg(s.cancelled ? tr(" (cancelled)") : QString()));
    });
    updateState();
}

void RenderBar::disarmRegionTool() {
    if (m_regionTool->isChecked()) m_regionTool->setChecked(false);
}

void RenderBar::syncFromDocument() {
    // What the bar said of the previous document's render does not describe this one.
    m_progress->setValue(0);
    m_info->clear();
    m_rendered = false;
    // A scene's own seed, integrator and MIS; the spp (low) and Halves (on: the studio's renders
    // are denoised, docs/lab/studio-halves.md) stay what the user chose.
    const render::Settings& s = m_document->settings();
    m_seed->setValue(int(std::min<std::uint64_t>(s.seed, std::uint64_t(m_seed->maximum()))));
    m_integrator->setCurrentIndex(m_integrator->findData(int(s.integrator)));
    m_mis->setCurrentIndex(m_mis->findData(int(s.mis)));
    if (m_document->kind() == Document::Kind::Scene) applySettings();
    updateState();
}

QString RenderBar::remaining() const {
    return m_remaining->text();
}

void RenderBar::showSettings() {
    const render::Settings& s = m_document->settings();
    const QSignalBlocker blocks[] = {QSignalBlocker(m_spp), QSignalBlocker(m_seed),
                                     QSignalBlocker(m_integrator), QSignalBlocker(m_mis),
                                     QSignalBlocker(m_halves)};
    m_spp->setValue(s.spp);
    m_seed->setValue(int(std::min<std::uint64_t>(s.seed, std::uint64_t(m_seed->maximum()))));
    m_integrator->setCurrentIndex(m_integrator->findData(int(s.integrator)));
    m_mis->setCurrentIndex(m_mis->findData(int(s.mis)));
    m_halves->setChecked(s.halfBuffers);
    updateState();
}

void RenderBar::controlChanged() {
    if (m_document->kind() != Document::Kind::Scene) return;
    try {
        applySettings();
    } catch (const Error& e) {
        emit failed(tr("Cannot use these render settings"), QString::fromStdString(e.what()));
    }
}

void RenderBar::applySettings() {
    render::Settings s = m_document->settings();
    s.spp = m_spp->value();
    s.seed = std::uint64_t(m_seed->value());
    s.integrator = render::Integrator(m_integrator->currentData().toInt());
    s.mis = render::MisHeuristic(m_mis->currentData().toInt());
    // Half buffers need path tracing and a sampler with independent halves: elsewhere the box
    // is disabled and the render has none.
    s.halfBuffers = m_halves->isChecked() && s.integrator == render::Integrator::Path &&
                    s.sampler != render::SamplerKind::Stratified;
    s.timeLimit = 0.0;
    m_document->setSettings(s);
}

void RenderBar::updateState() {
    const bool scene = m_document->kind() == Document::Kind::Scene;
    const bool rendering = m_document->rendering();
    for (QWidget* w : std::initializer_list<QWidget*>{m_spp, m_seed, m_integrator, m_mis, m_render,
                                                      m_regionTool, m_clearRegion})
        w->setEnabled(scene);
    m_halves->setEnabled(scene && render::Integrator(m_integrator->currentData().toInt()) ==
                                      render::Integrator::Path);
    m_pause->setEnabled(scene && rendering);
    m_cancel->setEnabled(scene && rendering);
    if (!rendering && m_pause->isChecked()) m_pause->setChecked(false);
}

}  // namespace glint::studio
