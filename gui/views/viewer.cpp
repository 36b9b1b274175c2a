#include "views/viewer.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyle>
#include <QStyleOptionComboBox>
#include <QToolButton>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <utility>

#include "glint/denoise/aids.h"
#include "glint/image/metrics.h"

namespace glint::studio {

namespace {

constexpr Viewer::Channel kChannels[] = {
    Viewer::Channel::Result,         Viewer::Channel::Render,
    Viewer::Channel::Albedo,         Viewer::Channel::Normal,
    Viewer::Channel::Depth,          Viewer::Channel::ColorVariance,
    Viewer::Channel::AlbedoVariance, Viewer::Channel::NormalVariance,
    Viewer::Channel::DepthVariance,  Viewer::Channel::SampleCount,
    Viewer::Channel::Reference,      Viewer::Channel::ErrorAbsolute,
    Viewer::Channel::ErrorSquared,   Viewer::Channel::ErrorRelative};

std::optional<Layer> layerOf(Viewer::Channel c) {
    switch (c) {
        case Viewer::Channel::Render:
            return Layer::Color;
        case Viewer::Channel::Albedo:
            return Layer::Albedo;
        case Viewer::Channel::Normal:
            return Layer::Normal;
        case Viewer::Channel::Depth:
            return Layer::Depth;
        case Viewer::Channel::ColorVariance:
            return Layer::Variance;
        case Viewer::Channel::AlbedoVariance:
            return Layer::AlbedoVariance;
        case Viewer::Channel::NormalVariance:
            return Layer::NormalVariance;
        case Viewer::Channel::DepthVariance:
            return Layer::DepthVariance;
        case Viewer::Channel::SampleCount:
            return Layer::SampleCount;
        default:
            return std::nullopt;
    }
}

QString formatPixel(const Image& image, int x, int y) {
    if (image.empty() || x >= image.width() || y >= image.height()) return {};
    QStringList parts;
    for (int c = 0; c < image.channels(); ++c) parts << QString::number(image(x, y, c), 'g', 4);
    return parts.join(QLatin1Char(' '));
}

}  // namespace

QString channelName(Viewer::Channel channel) {
    switch (channel) {
        case Viewer::Channel::Result:
            return Viewer::tr("Result");
        case Viewer::Channel::Render:
            return Viewer::tr("Render (unfiltered)");
        case Viewer::Channel::Albedo:
            return Viewer::tr("Albedo");
        case Viewer::Channel::Normal:
            return Viewer::tr("Normal");
        case Viewer::Channel::Depth:
            return Viewer::tr("Depth (equalised)");
        case Viewer::Channel::ColorVariance:
            return Viewer::tr("Colour variance");
        case Viewer::Channel::AlbedoVariance:
            return Viewer::tr("Albedo variance");
        case Viewer::Channel::NormalVariance:
            return Viewer::tr("Normal variance");
        case Viewer::Channel::DepthVariance:
            return Viewer::tr("Depth variance");
        case Viewer::Channel::SampleCount:
            return Viewer::tr("Sample count");
        case Viewer::Channel::Reference:
            return Viewer::tr("Reference");
        case Viewer::Channel::ErrorAbsolute:
            return Viewer::tr("Error: absolute");
        case Viewer::Channel::ErrorSquared:
            return Viewer::tr("Error: squared");
        case Viewer::Channel::ErrorRelative:
            return Viewer::tr("Error: relative");
    }
    return {};
}

QString channelKey(Viewer::Channel channel) {
    switch (channel) {
        case Viewer::Channel::Result:
            return QStringLiteral("result");
        case Viewer::Channel::Render:
            return QStringLiteral("render");
        case Viewer::Channel::Albedo:
            return QStringLiteral("albedo");
        case Viewer::Channel::Normal:
            return QStringLiteral("normal");
        case Viewer::Channel::Depth:
            return QStringLiteral("depth");
        case Viewer::Channel::ColorVariance:
            return QStringLiteral("colorVariance");
        case Viewer::Channel::AlbedoVariance:
            return QStringLiteral("albedoVariance");
        case Viewer::Channel::NormalVariance:
            return QStringLiteral("normalVariance");
        case Viewer::Channel::DepthVariance:
            return QStringLiteral("depthVariance");
        case Viewer::Channel::SampleCount:
            return QStringLiteral("sampleCount");
        case Viewer::Channel::Reference:
            return QStringLiteral("reference");
        case Viewer::Channel::ErrorAbsolute:
            return QStringLiteral("errorAbsolute");
        case Viewer::Channel::ErrorSquared:
            return QStringLiteral("errorSquared");
        case Viewer::Channel::ErrorRelative:
            return QStringLiteral("errorRelative");
    }
    return {};
}

std::optional<Viewer::Channel> channelFromKey(const QString& key) {
    for (Viewer::Channel c : kChannels)
        if (channelKey(c) == key) return c;
    return std::nullopt;
}

bool isStatistic(Viewer::Channel channel) {
    return channel == Viewer::Channel::ColorVariance ||
           channel == Viewer::Channel::AlbedoVariance ||
           channel == Viewer::Channel::NormalVariance ||
           channel == Viewer::Channel::DepthVariance || channel == Viewer::Channel::SampleCount;
}

Viewer::Viewer(Document* document, SessionAdapter* session, QWidget* parent)
    : QWidget(parent), m_document(document), m_session(session) {
    m_canvas = new ImageCanvas(this);
    m_channelBox = new QComboBox(this);
    for (Channel c : kChannels) m_channelBox->addItem(channelName(c), int(c));
    m_channelBox->setToolTip(
        tr("What the canvas shows: the result, a feature, a variance, the reference or an error "
           "image"));
    m_exposure = new QDoubleSpinBox(this);
    m_exposure->setRange(-20.0, 20.0);
    m_exposure->setSingleStep(0.5);
    m_exposure->setPrefix(tr("EV "));
    m_exposure->setToolTip(tr("Exposure in stops: values are multiplied by 2^EV (E / Shift+E)"));
    m_offset = new QDoubleSpinBox(this);
    m_offset->setRange(-10.0, 10.0);
    m_offset->setSingleStep(0.01);
    m_offset->setDecimals(3);
    m_offset->setPrefix(tr("offset "));
    m_offset->setToolTip(tr("Added to every value after the exposure"));
    m_mode = new QComboBox(this);
    m_mode->addItem(tr("sRGB"), int(DisplayMode::Srgb));
    m_mode->addItem(tr("Linear"), int(DisplayMode::Linear));
    m_mode->addItem(tr("False colour"), int(DisplayMode::FalseColor));
    m_mode->setToolTip(tr("How values reach the screen"));
    m_autoRange = new QToolButton(this);
    m_autoRange->setText(tr("Auto"));
    m_autoRange->setCheckable(true);
    m_autoRange->setChecked(true);
    m_autoRange->setToolTip(
        tr("False colour spans the 1st to 99th percentile of the shown values (off: 0 to 1)"));
    m_autoRange->setVisible(false);
    auto* fit = new QToolButton(this);
    fit->setText(tr("Fit"));
    fit->setToolTip(tr("Fit the image to the window (F)"));
    auto* one = new QToolButton(this);
    one->setText(tr("1:1"));
    one->setToolTip(tr("One image pixel per screen pixel (0)"));
    m_flip = new QToolButton(this);
    m_flip->setText(tr("A/B"));
    m_flip->setCheckable(true);
    m_flip->setToolTip(tr("Show the reference instead of the result (Space)"));
    m_wipeBox = new QCheckBox(tr("Wipe"), this);
    m_wipeBox->setToolTip(
        tr("Result left of the line, reference right of it; drag the line on the canvas (V)"));
    m_wipe = new QSlider(Qt::Horizontal, this);
    m_wipe->setRange(0, 1000);
    m_wipe->setValue(500);
    m_wipe->setMaximumWidth(160);
    // The bar gives way before the window outgrows a 1366-px screen.
    m_wipe->setMinimumWidth(32);
    // The channel box is as wide as its longest item when there is room and gives way down to
    // ten characters, never below its current item (fitChannelBox: ten cut "Colour variance" and
    // "Error: relative" at 1280×720 and 1366×768, the screenshot tour's walk at those sizes;
    // every item's width would make the window wider than 1280; the wipe slider and the gap
    // before A/B give way instead); the display mode (three short
    // items) always shows its item whole ("False colour"). The Auto button that false colour shows
    // keeps its place when hidden, so the bar is as wide in every mode: panels that took the
    // viewer's spare width never squeeze the channel box when false colour is turned on.
    m_channelBox->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    m_channelBox->setMinimumContentsLength(10);
    fitChannelBox();
    QSizePolicy keep = m_autoRange->sizePolicy();
    keep.setRetainSizeWhenHidden(true);
    m_autoRange->setSizePolicy(keep);
    m_mode->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    m_wipe->setEnabled(false);

    auto* bar = new QHBoxLayout;
    bar->setContentsMargins(4, 2, 4, 2);
    bar->addWidget(m_channelBox);
    bar->addWidget(m_exposure);
    bar->addWidget(m_offset);
    bar->addWidget(m_mode);
    bar->addWidget(m_autoRange);
    bar->addWidget(fit);
    bar->addWidget(one);
    bar->addSpacing(6);
    bar->addWidget(m_flip);
    bar->addWidget(m_wipeBox);
    bar->addWidget(m_wipe);
    bar->addStretch(1);
    auto* layout = new QVBoxLayout(this);
    layout->setContentsMargins(0, 0, 0, 0);
    layout->setSpacing(0);
    layout->addLayout(bar);
    layout->addWidget(m_canvas, 1);

    connect(m_channelBox, &QComboBox::currentIndexChanged, this,
            [this](int i) { setChannel(Channel(m_channelBox->itemData(i).toInt())); });
    connect(m_exposure, &QDoubleSpinBox::valueChanged, this, &Viewer::applyDisplay);
    connect(m_exposure, &QDoubleSpinBox::valueChanged, this, &Viewer::exposureChanged);
    connect(m_offset, &QDoubleSpinBox::valueChanged, this, &Viewer::applyDisplay);
    connect(m_mode, &QComboBox::currentIndexChanged, this, &Viewer::applyDisplay);
    connect(m_autoRange, &QToolButton::toggled, this, &Viewer::applyDisplay);
    connect(fit, &QToolButton::clicked, m_canvas, &ImageCanvas::fit);
    connect(one, &QToolButton::clicked, m_canvas, &ImageCanvas::oneToOne);
    connect(m_flip, &QToolButton::toggled, this, &Viewer::setFlipped);
    connect(m_wipeBox, &QCheckBox::toggled, this, &Viewer::setWipe);
    connect(m_wipe, &QSlider::valueChanged, this, [this](int v) {
        if (m_wipeBox->isChecked()) m_canvas->setWipe(v / 1000.0);
    });
    connect(m_canvas, &ImageCanvas::hovered, this, &Viewer::updateReadout);
    connect(m_canvas, &ImageCanvas::wipeMoved, this, [this](double fraction) {
        const QSignalBlocker block(m_wipe);
        m_wipe->setValue(int(std::lround(fraction * 1000.0)));
    });

    connect(m_document, &Document::frameChanged, this, [this](bool) { refresh(); });
    connect(m_document, &Document::referenceChanged, this, [this] {
        updateCompare();
        refresh();
    });
    connect(m_session, &SessionAdapter::compositeChanged, this, &Viewer::onCompositeChanged);
    connect(m_session, &SessionAdapter::sessionReset, this, &Viewer::refresh);
    connect(m_session, &SessionAdapter::layersChanged, this, &Viewer::updateLabel);
    connect(m_document, &Document::renderingChanged, this, [this](bool) { updateLabel(); });
}

bool Viewer::keepsDenoised() const {
    // A denoised composite stays on screen while a new render refines: its first passes are
    // noisier than it. The new render shows denoised once a pass has as many samples per pixel
    // (ProgressiveDenoise re-applies the layers to it), and again when it is finished.
    return m_session->hasSession() && m_session->session().layerCount() > 0;
}

bool Viewer::showingComposite() const {
    // While a render refines without layers to keep, the result is the render itself.
    return m_channel == Channel::Result && m_session->hasSession() &&
           (keepsDenoised() ||
            !(m_document->rendering() && m_document->frame() != m_document->finishedFrame()));
}

const Image* Viewer::resultImage() const {
    if (m_session->hasSession() &&
        (keepsDenoised() ||
         !(m_document->rendering() && m_document->frame() != m_document->finishedFrame())))
        return &m_session->session().composite();
    if (FramePtr f = m_document->frame()) return &f->color();
    return nullptr;
}

void Viewer::setChannel(Channel channel) {
    m_channel = channel;
    const int index = m_channelBox->findData(int(channel));
    if (index != m_channelBox->currentIndex()) m_channelBox->setCurrentIndex(index);
    fitChannelBox();
    refresh();
    emit channelChanged(channel);
}

void Viewer::fitChannelBox() {
    QStyleOptionComboBox option;
    option.initFrom(m_channelBox);
    const QFontMetrics fm(m_channelBox->font());
    const QSize text(fm.horizontalAdvance(m_channelBox->currentText()), fm.height());
    const int needed = m_channelBox->style()
                           ->sizeFromContents(QStyle::CT_ComboBox, &option, text, m_channelBox)
                           .width() +
                       1;
    m_channelBox->setMinimumWidth(std::min(needed, m_channelBox->sizeHint().width()));
}

void Viewer::holdRedraws(bool held) {
    m_held = held;
    if (!held && std::exchange(m_redrawWaits, false)) refresh();
}

void Viewer::refresh() {
    if (m_held) {
        m_redrawWaits = true;
        return;
    }
    FramePtr frame = m_document->frame();
    FramePtr reference = m_document->reference();
    const Image* result = resultImage();
    if (!frame || !result) return;
    m_statScale = 0.0f;
    if (m_channel == Channel::Result) {
        m_canvas->setImage(*result);
    } else if (m_channel == Channel::Reference) {
        if (reference) m_canvas->setImage(reference->color());
    } else if (m_channel == Channel::ErrorAbsolute || m_channel == Channel::ErrorSquared ||
               m_channel == Channel::ErrorRelative) {
        if (!reference || reference->width() != result->width() ||
            reference->height() != result->height()) {
            m_canvas->setImage(*result);
            updateLabel();
            return;
        }
        if (m_channel == Channel::ErrorRelative) {
            m_shown = relErrorMap(*result, reference->color());
        } else {
            m_shown = absErrorMap(*result, reference->color());
            if (m_channel == Channel::ErrorSquared)
                for (float& v : m_shown.data()) v *= v;
        }
        m_canvas->setImage(m_shown);
    } else if (std::optional<Layer> layer = layerOf(m_channel); layer && frame->has(*layer)) {
        // Features as the filters see them: prefiltered when the session says so.
        FramePtr features = m_session->options().prefilter && m_session->filterInput() &&
                                    *layer != Layer::Color && *layer != Layer::Variance &&
                                    *layer != Layer::SampleCount
                                ? m_session->filterInput()
                                : frame;
        const Image& source =
            features->has(*layer) ? features->layer(*layer) : frame->layer(*layer);
        if (m_channel == Channel::Normal) {
            // Components in [−1, 1] shown as colours in [0, 1].
            m_shown = source;
            for (float& v : m_shown.data()) v = 0.5f * v + 0.5f;
        } else if (m_channel == Channel::Depth) {
            m_shown = denoise::equalizeHistogram(source);
        } else if (isStatistic(m_channel)) {
            // Variances and counts are tiny or large numbers: divided by their 99th percentile
            // so that they read at EV 0 (the label says by what; the read-out stays raw).
            m_shown = source;
            m_statScale = normalizeForDisplay(m_shown);
        } else {
            m_shown = source;
        }
        m_canvas->setImage(m_shown);
    } else {
        m_canvas->setImage(*result);  // the layer is absent: show the result
    }
    updateReadout(m_hoverX, m_hoverY);
    updateLabel();
}

void Viewer::onCompositeChanged(const Rect& rect) {
    if (m_held) {
        m_redrawWaits = true;
        return;
    }
    if (!showingComposite()) {
        if (m_channel != Channel::Result) return;
        refresh();
        return;
    }
    const Image& composite = m_session->session().composite();
    const bool whole = rect.x0 <= 0 && rect.y0 <= 0 && rect.x1 >= composite.width() &&
                       rect.y1 >= composite.height();
    if (whole)
        m_canvas->setImage(composite);
    else
        m_canvas->updateImage(composite, rect);
}

void Viewer::updateCompare() {
    FramePtr reference = m_document->reference();
    m_canvas->setCompareImage(reference ? &reference->color() : nullptr);
}

void Viewer::setFlipped(bool on) {
    if (m_flip->isChecked() != on) m_flip->setChecked(on);
    m_canvas->setFlipped(on);
    updateLabel();
}

void Viewer::toggleFlip() {
    setFlipped(!m_canvas->flipped());
}

void Viewer::setWipe(bool on) {
    if (m_wipeBox->isChecked() != on) m_wipeBox->setChecked(on);
    m_wipe->setEnabled(on);
    m_canvas->setWipe(on ? std::optional<double>(m_wipe->value() / 1000.0) : std::nullopt);
    updateLabel();
}

void Viewer::toggleWipe() {
    setWipe(!m_wipeBox->isChecked());
}

bool Viewer::wipe() const {
    return m_wipeBox->isChecked();
}

void Viewer::setAutoRange(bool on) {
    m_autoRange->setChecked(on);
}

void Viewer::updateLabel() {
    FramePtr frame = m_document->frame();
    FramePtr reference = m_document->reference();
    const Image* result = resultImage();
    auto spp = [](const FramePtr& f) {
        return f && f->metadata().spp > 0 ? tr(" (%1 spp)").arg(f->metadata().spp) : QString();
    };
    const bool haveB = reference && result && reference->width() == result->width() &&
                       reference->height() == result->height();
    QString what;
    if (m_channel == Channel::Result) {
        if (!frame)
            what = QString();
        else if (showingComposite() && keepsDenoised())
            what =
                m_document->refining() ? tr("Result (denoised, %1 spp; refining…)")
                                             .arg(m_session->input()->metadata().spp)
                : !(m_document->rendering() && m_document->frame() != m_document->finishedFrame())
                    ? tr("Result (denoised, %1 spp)").arg(m_session->input()->metadata().spp)
                // A pass of the running render, denoised (ProgressiveDenoise), or still the
                // previous render until a pass is as good.
                : m_session->input() == m_document->finishedFrame()
                    ? tr("Result (denoised, previous render; rendering…)")
                    : tr("Result (denoised, %1 spp; rendering…)")
                          .arg(m_session->input()->metadata().spp);
        else
            what = tr("Result (render, %1 spp)").arg(frame->metadata().spp);
    } else if (m_channel == Channel::Reference) {
        what = reference ? tr("Reference") + spp(reference) : tr("Result (no reference)");
    } else {
        what = channelName(m_channel);
        if (m_statScale > 0.0f)
            what =
                tr("%1 (normalised ÷ %2)").arg(what, QString::number(double(m_statScale), 'g', 3));
    }
    QString text = what;
    if (haveB && m_canvas->flipped())
        text = tr("B: Reference") + spp(reference);
    else if (haveB && m_wipeBox->isChecked())
        text = tr("Wipe: %1 | reference")
                   .arg(m_channel == Channel::Result ? tr("result") : channelName(m_channel));
    else if (haveB && m_channel == Channel::Result && !what.isEmpty())
        text = tr("A: %1").arg(what);
    m_canvas->setLabel(text);
}

void Viewer::setExposure(double stops) {
    m_exposure->setValue(stops);
}

double Viewer::exposure() const {
    return m_exposure->value();
}

void Viewer::setDisplayMode(DisplayMode mode) {
    m_mode->setCurrentIndex(m_mode->findData(int(mode)));
}

void Viewer::applyDisplay() {
    DisplaySettings d;
    d.exposure = float(m_exposure->value());
    d.offset = float(m_offset->value());
    d.mode = DisplayMode(m_mode->currentData().toInt());
    d.autoRange = m_autoRange->isChecked();
    m_autoRange->setVisible(d.mode == DisplayMode::FalseColor);
    m_canvas->setDisplay(d);
}

void Viewer::updateReadout(int x, int y) {
    m_hoverX = x;
    m_hoverY = y;
    FramePtr frame = m_document->frame();
    if (x < 0 || y < 0 || !frame || x >= frame->width() || y >= frame->height()) {
        m_readout.clear();
        emit readoutChanged(m_readout);
        return;
    }
    // Most wanted first (the status bar shows what fits of it): the result and the reference,
    // the render's colour and features, then the features' variances and the half buffers.
    QStringList parts;
    parts << tr("(%1, %2)").arg(x).arg(y);
    if (const Image* result = resultImage())
        parts << tr("result %1").arg(formatPixel(*result, x, y));
    if (FramePtr reference = m_document->reference();
        reference && x < reference->width() && y < reference->height())
        parts << tr("reference %1").arg(formatPixel(reference->color(), x, y));
    constexpr Layer kFirst[] = {Layer::Color, Layer::Variance, Layer::Albedo,     Layer::Normal,
                                Layer::Depth, Layer::Position, Layer::SampleCount};
    auto add = [&](Layer layer) {
        const std::string_view name = layerDisplayName(layer);
        parts << QStringLiteral("%1 %2").arg(QString::fromUtf8(name.data(), qsizetype(name.size())),
                                             formatPixel(frame->layer(layer), x, y));
    };
    for (Layer layer : kFirst)
        if (frame->has(layer)) add(layer);
    for (int l = 0; l < kLayerCount; ++l)
        if (frame->has(Layer(l)) &&
            std::find(std::begin(kFirst), std::end(kFirst), Layer(l)) == std::end(kFirst))
            add(Layer(l));
    m_readout = parts.join(QStringLiteral("  ·  "));
    emit readoutChanged(m_readout);
}

}  // namespace glint::studio
