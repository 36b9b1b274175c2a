#include "views/features_view.h"

#include <QCheckBox>
#include <QGridLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include "glint/denoise/prefilter.h"

namespace glint::studio {

FeaturesView::FeaturesView(const StudioContext& context, QWidget* parent)
    : StageView(context, parent) {
    auto* grid = new QGridLayout;
    const std::pair<Viewer::Channel, Viewer::Channel> rows[] = {
        {Viewer::Channel::Albedo, Viewer::Channel::AlbedoVariance},
        {Viewer::Channel::Normal, Viewer::Channel::NormalVariance},
        {Viewer::Channel::Depth, Viewer::Channel::DepthVariance},
        {Viewer::Channel::Result, Viewer::Channel::ColorVariance}};
    int row = 0;
    for (const auto& [a, b] : rows) {
        int col = 0;
        for (Viewer::Channel c : {a, b}) {
            auto* button = new QPushButton(channelName(c), this);
            button->setToolTip(tr("Show %1 on the canvas").arg(channelName(c).toLower()));
            connect(button, &QPushButton::clicked, this,
                    [this, c] { m_context.viewer->setChannel(c); });
            grid->addWidget(button, row, col++);
        }
        ++row;
    }
    auto* count = new QPushButton(channelName(Viewer::Channel::SampleCount), this);
    connect(count, &QPushButton::clicked, this,
            [this] { m_context.viewer->setChannel(Viewer::Channel::SampleCount); });
    grid->addWidget(count, row, 0);

    m_prefilter = new QCheckBox(tr("Prefilter the features"), this);
    m_prefilter->setToolTip(
        tr("Smooth albedo, normal and depth made noisy by motion blur or depth "
           "of field before the filters use them"));
    m_params = new ParamControls(this);
    m_params->setSpecs(denoise::prefilterParams(), {});
    auto* apply = new QPushButton(tr("Apply prefilter settings"), this);
    m_info = new QLabel(this);
    m_info->setWordWrap(true);
    auto* layout = new QVBoxLayout(this);
    layout->addLayout(grid);
    layout->addSpacing(8);
    layout->addWidget(m_prefilter);
    layout->addWidget(m_params);
    layout->addWidget(apply);
    layout->addWidget(m_info);
    layout->addStretch(1);

    connect(m_prefilter, &QCheckBox::toggled, this, &FeaturesView::setPrefilter);
    connect(apply, &QPushButton::clicked, this, [this] { setPrefilter(m_prefilter->isChecked()); });
    connect(m_context.session, &SessionAdapter::sessionReset, this, &FeaturesView::updateInfo);
    connect(m_context.document, &Document::frameChanged, this, &FeaturesView::updateInfo);
    updateInfo();
}

void FeaturesView::setPrefilter(bool on) {
    if (m_prefilter->isChecked() != on) {
        m_prefilter->setChecked(on);  // re-enters through toggled
        return;
    }
    denoise::SessionOptions options;
    options.prefilter = on;
    options.prefilterParams = m_params->values();
    m_context.session->setOptions(options);
    updateInfo();
}

void FeaturesView::activate() {
    m_context.viewer->canvas()->setTool(ImageCanvas::Tool::Pan);
}

void FeaturesView::deactivate() {
    // Back to the result when the features stage is left.
    m_context.viewer->setChannel(Viewer::Channel::Result);
}

void FeaturesView::updateInfo() {
    FramePtr frame = m_context.document->frame();
    if (!frame) {
        m_info->setText(tr("No image yet."));
        return;
    }
    QStringList missing;
    for (Layer l : {Layer::Albedo, Layer::Normal, Layer::Depth})
        if (!frame->has(l))
            missing << QString::fromUtf8(layerDisplayName(l).data(),
                                         qsizetype(layerDisplayName(l).size()));
    QString text = missing.isEmpty() ? tr("The render has albedo, normal and depth.")
                                     : tr("Missing features: %1 (filters that need them are "
                                          "refused).")
                                           .arg(missing.join(QStringLiteral(", ")));
    if (m_context.session->options().prefilter)
        text += QLatin1Char(' ') + tr("The filters read prefiltered features (shown in the feature "
                                      "channels); changing this starts a new undo history.");
    m_info->setText(text);
}

}  // namespace glint::studio
