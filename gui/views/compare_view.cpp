#include "views/compare_view.h"

#include <QCheckBox>
#include <QComboBox>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QTableWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <limits>

#include "glint/image/flip.h"
#include "glint/image/metrics.h"
#include "model/render_eta.h"
#include "views/canvas_overlays.h"

namespace glint::studio {

namespace {

/// HDR-FLIP of `image` against `reference`: its mean over the image and over `rect` (of the
/// image's map: the filters see the whole image) and the map; NaN means when FLIP cannot be
/// computed (a mostly black reference, a non-finite value).
struct FlipMeans {
    double image = std::numeric_limits<double>::quiet_NaN();
    double region = std::numeric_limits<double>::quiet_NaN();
    Image map;
};

FlipMeans hdrFlip(const Image& image, const Image& reference, const Rect& rect) {
    FlipMeans f;
    try {
        FlipOptions options;
        options.hdr = true;
        FlipResult r = flip(image, reference, options);
        double sum = 0.0;
        for (int y = rect.y0; y < rect.y1; ++y)
            for (int x = rect.x0; x < rect.x1; ++x) sum += r.map(x, y, 0);
        f.image = r.mean;
        f.region = rect.empty() ? f.image : sum / (double(rect.width()) * rect.height());
        f.map = std::move(r.map);
    } catch (const Error&) {
        // Left NaN: the table shows a dash.
    }
    return f;
}

}  // namespace

CompareView::CompareView(const StudioContext& context, QWidget* parent)
    : StageView(context, parent) {
    auto* open = new QPushButton(tr("Open reference…"), this);
    open->setToolTip(tr("A high-spp EXR of the same scene and size"));
    m_spp = new QSpinBox(this);
    m_spp->setRange(16, 1 << 16);
    m_spp->setValue(1024);
    m_spp->setPrefix(tr("spp "));
    auto* render = new QPushButton(tr("Render reference"), this);
    render->setToolTip(tr("Render the current look at this spp in the background while you work"));
    auto* clear = new QPushButton(tr("Clear"), this);
    m_progress = new QProgressBar(this);
    m_progress->setRange(0, 1000);
    // The reference render's samples and time left (model/render_eta.h) on the bar.
    m_progress->setFormat(QString());
    // The raw render beside the result: two columns, one metric a row, the image's four rows
    // then the region's (four columns of seven-character figures do not fit a laptop's panel).
    m_table = new QTableWidget(8, 2, this);
    m_table->setHorizontalHeaderLabels({tr("Raw"), tr("Result")});
    m_table->setVerticalHeaderLabels({tr("SSIM"), tr("relMSE"), tr("PSNR dB"), tr("FLIP"),
                                      tr("Region SSIM"), tr("Region relMSE"), tr("Region PSNR"),
                                      tr("Region FLIP")});
    m_table->setEditTriggers(QAbstractItemView::NoEditTriggers);
    m_table->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
    m_table->setVerticalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    m_table->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    m_table->resizeRowsToContents();
    // As tall as its header and rows as they are (no blank band under them: at 1366×768 every
    // pixel of the panel counts).
    int rows = 0;
    for (int r = 0; r < m_table->rowCount(); ++r) rows += m_table->rowHeight(r);
    m_table->setFixedHeight(m_table->horizontalHeader()->sizeHint().height() + rows +
                            2 * m_table->frameWidth());
    m_table->setToolTip(
        tr("Against the reference, over the whole image and over the region's bounding box: "
           "Raw is the render the result was made from (the convergence plot's last point is "
           "its relMSE over the image), Result the composite of the layers. FLIP is HDR-FLIP's "
           "mean error (0 none, 1 most); in the region, the image's map averaged there"));
    m_verdict = new QLabel(this);
    m_verdict->setWordWrap(true);
    m_lookWarning = new QLabel(this);
    m_lookWarning->setWordWrap(true);
    m_lookWarning->setStyleSheet(QStringLiteral("color: #d04020;"));
    m_lookWarning->hide();
    m_stats = new QLabel(this);
    m_stats->setWordWrap(true);
    m_stats->setTextInteractionFlags(Qt::TextSelectableByMouse);
    m_error = new QComboBox(this);
    m_error->addItem(tr("Result"), int(Viewer::Channel::Result));
    m_error->addItem(tr("Reference"), int(Viewer::Channel::Reference));
    for (Viewer::Channel c : {Viewer::Channel::ErrorAbsolute, Viewer::Channel::ErrorSquared,
                              Viewer::Channel::ErrorRelative})
        m_error->addItem(channelName(c), int(c));
    m_error->setToolTip(tr("What the canvas shows: the result, the reference or an error image"));
    m_flipMap = new QCheckBox(tr("FLIP map over the canvas"), this);
    m_flipMap->setObjectName(QStringLiteral("flipMap"));
    m_flipMap->setToolTip(
        tr("The result's HDR-FLIP error against the reference, per pixel, in magma: black where "
           "a viewer sees no difference, pale yellow where it is most visible"));
    // The plot measures the raw passes (the table's Raw column), not the result: it says so.
    m_axis = new QComboBox(this);
    m_axis->addItem(tr("Plot: raw render's relMSE vs seconds"));
    m_axis->addItem(tr("Plot: raw render's relMSE vs spp"));
    m_axis->setToolTip(
        tr("relMSE of each pass of the raw render (not the denoised result) against the "
           "reference, over the whole image: the table's Raw, image figure once it finishes"));
    m_plot = new ConvergencePlot(this);

    auto* row1 = new QHBoxLayout;
    row1->addWidget(open);
    row1->addWidget(clear);
    auto* row2 = new QHBoxLayout;
    row2->addWidget(m_spp);
    row2->addWidget(render);
    auto* layout = new QVBoxLayout(this);
    layout->addLayout(row1);
    layout->addLayout(row2);
    layout->addWidget(m_progress);
    layout->addWidget(m_error);
    layout->addWidget(m_flipMap);
    layout->addWidget(m_lookWarning);
    layout->addWidget(m_table);
    layout->addWidget(m_verdict);
    layout->addWidget(m_stats);
    layout->addWidget(m_axis);
    layout->addWidget(m_plot, 1);

    connect(open, &QPushButton::clicked, this, &CompareView::openReferenceRequested);
    connect(render, &QPushButton::clicked, this, [this] {
        try {
            m_progress->setValue(0);
            m_context.document->renderReference(m_spp->value());
        } catch (const Error& e) {
            emit failed(tr("Cannot render the reference"), QString::fromStdString(e.what()));
        }
    });
    connect(clear, &QPushButton::clicked, m_context.document, &Document::clearReference);
    connect(m_error, &QComboBox::currentIndexChanged, this, [this](int i) {
        m_context.viewer->setChannel(Viewer::Channel(m_error->itemData(i).toInt()));
    });
    connect(m_flipMap, &QCheckBox::toggled, this, &CompareView::showFlipMap);
    connect(m_axis, &QComboBox::currentIndexChanged, this,
            [this](int i) { m_plot->setAgainstSpp(i == 1); });
    connect(m_context.document, &Document::referenceProgress, this,
            [this](double f, int spp, int total, double left) {
                m_progress->setValue(int(f * 1000.0));
                m_progress->setFormat(formatSamplesLeft(spp, total, left));
            });
    connect(m_context.document, &Document::referenceChanged, this, [this] {
        if (m_context.document->reference()) m_progress->setValue(1000);
        m_progress->setFormat(QString());
        updateLookWarning();
        schedule();
    });
    connect(m_context.document, &Document::lookChanged, this, &CompareView::updateLookWarning);
    connect(m_context.document, &Document::curveChanged, this,
            [this] { m_plot->setPoints(m_context.document->curve()); });
    connect(m_context.document, &Document::frameChanged, this, &CompareView::schedule);
    connect(m_context.session, &SessionAdapter::compositeChanged, this, &CompareView::schedule);
    connect(m_context.region, &RegionOfInterest::changed, this, &CompareView::schedule);
    m_debounce.setSingleShot(true);
    m_debounce.setInterval(150);
    connect(&m_debounce, &QTimer::timeout, this, &CompareView::measure);
    show();
}

QString CompareView::lookWarning() const {
    return m_lookWarning->isHidden() ? QString() : m_lookWarning->text();
}

bool CompareView::metricsStale() const {
    return m_context.document->referenceLookDiffers();
}

void CompareView::updateLookWarning() {
    QString text;
    switch (m_context.document->referenceMismatch()) {
        case ReferenceMismatch::None:
            break;
        case ReferenceMismatch::Scene:
            text =
                tr("The reference was rendered for another scene (%1): its metrics are stale. Open "
                   "or render a reference of this one.")
                    .arg(QFileInfo(
                             QString::fromStdString(m_context.document->referenceInfo()->scene))
                             .fileName());
            break;
        case ReferenceMismatch::Look:
            text =
                tr("The reference was rendered with another look (the look was edited since): its "
                   "metrics are stale. Render it again, or undo the look edit.");
            break;
        case ReferenceMismatch::Camera:
            text =
                tr("The reference was rendered through another camera: its metrics are stale. "
                   "Render it again.");
            break;
        case ReferenceMismatch::Unknown:
            text =
                tr("Not known what the reference was rendered for (it names no scene): check it "
                   "shows this scene and look.");
            break;
    }
    m_lookWarning->setText(text);
    m_lookWarning->setVisible(!text.isEmpty());
    const bool differs = metricsStale();
    if (differs && !m_warnedLook) emit status(text);
    m_warnedLook = differs;
    show();
}

void CompareView::schedule() {
    m_debounce.start();
}

void CompareView::measure() {
    const Image* result = m_context.viewer->resultImage();
    if (!result) return;
    FramePtr reference = m_context.document->reference();
    // The raw render the result was made from.
    FramePtr raw = m_context.session->input();
    const Rect rect = m_context.region->bounds(result->width(), result->height());
    auto image = std::make_shared<const Image>(*result);
    auto mask =
        std::make_shared<const Image>(m_context.region->mask(result->width(), result->height()));
    m_tasks.run<Measurement>(
        QStringLiteral("measure"),
        [image, reference, raw, rect, mask](const TaskRunner::CancelFlag&) {
            Measurement m;
            // Per-channel statistics of the result inside the region.
            std::array<double, 3> sum{};
            double count = 0.0;
            m.min.fill(std::numeric_limits<double>::infinity());
            m.max.fill(-std::numeric_limits<double>::infinity());
            for (int y = rect.y0; y < rect.y1; ++y)
                for (int x = rect.x0; x < rect.x1; ++x) {
                    if ((*mask)(x, y, 0) <= 0.0f) continue;
                    count += 1.0;
                    for (int c = 0; c < 3; ++c) {
                        const double v = (*image)(x, y, c);
                        m.min[std::size_t(c)] = std::min(m.min[std::size_t(c)], v);
                        m.max[std::size_t(c)] = std::max(m.max[std::size_t(c)], v);
                        sum[std::size_t(c)] += v;
                    }
                }
            for (int c = 0; c < 3; ++c)
                m.mean[std::size_t(c)] = count > 0 ? sum[std::size_t(c)] / count : 0.0;
            if (reference && reference->width() == image->width() &&
                reference->height() == image->height()) {
                m.haveReference = true;
                const Image& ref = reference->color();
                MetricOptions whole, region;
                region.crop = rect;
                m.ssimImage = ssim(*image, ref, whole).value;
                m.relMseImage = relMse(*image, ref, whole).value;
                m.psnrImage = psnr(*image, ref, whole).value;
                m.ssimRegion = ssim(*image, ref, region).value;
                m.relMseRegion = relMse(*image, ref, region).value;
                m.psnrRegion = psnr(*image, ref, region).value;
                FlipMeans f = hdrFlip(*image, ref, rect);
                m.flipImage = f.image;
                m.flipRegion = f.region;
                if (!f.map.empty()) m.flipMap = flipOverlay(f.map);
                if (raw && raw->width() == image->width() && raw->height() == image->height()) {
                    m.haveRaw = true;
                    const Image& r = raw->color();
                    m.rawImage = {ssim(r, ref, whole).value, relMse(r, ref, whole).value,
                                  psnr(r, ref, whole).value};
                    m.rawRegion = {ssim(r, ref, region).value, relMse(r, ref, region).value,
                                   psnr(r, ref, region).value};
                    const FlipMeans rawFlip = hdrFlip(r, ref, rect);
                    m.rawImage.flip = rawFlip.image;
                    m.rawRegion.flip = rawFlip.region;
                }
            }
            return m;
        },
        [this](Measurement m) {
            m_measurement = m;
            show();
            showFlipMap();
            emit measured();
        });
}

QString compactNumber(double v) {
    if (v == 0.0 || !std::isfinite(v)) return QString::number(v);
    // Plain from 0.001 to 9999, to three significant digits (four and more above 1000).
    const int exponent = int(std::floor(std::log10(std::abs(v))));
    if (exponent >= -3 && exponent <= 3) return QString::number(v, 'f', std::max(0, 2 - exponent));
    // Else the exponent form without its padding: "7.51e-4", "1.23e5".
    QString text = QString::number(v, 'e', 2);
    const qsizetype e = text.indexOf(QLatin1Char('e'));
    QString power = text.mid(e + 1);
    const bool negative = power.startsWith(QLatin1Char('-'));
    power.remove(0, 1);  // the sign
    while (power.size() > 1 && power.startsWith(QLatin1Char('0'))) power.remove(0, 1);
    return text.left(e + 1) + (negative ? QStringLiteral("-") : QString()) + power;
}

namespace {

// The table's row of a metric (0 SSIM, 1 relMSE, 2 PSNR, 3 FLIP) and its column (0 raw, 1 result)
// for cellText's columns (raw, result, raw in the region, result in the region).
int tableRow(int row, int column) {
    return row + 4 * (column / 2);
}

}  // namespace

QString CompareView::columnTitle(int column) const {
    const QTableWidgetItem* item = m_table->horizontalHeaderItem(column % 2);
    if (!item) return {};
    return column < 2 ? tr("%1, image").arg(item->text()) : tr("%1, region").arg(item->text());
}

QString CompareView::cellText(int row, int column) const {
    const QTableWidgetItem* item = m_table->item(tableRow(row, column), column % 2);
    return item ? item->text() : QString();
}

QString CompareView::verdict() const {
    return m_verdict->text();
}

QString CompareView::plotTitle() const {
    return m_axis->currentText();
}

void CompareView::setFlipMapShown(bool shown) {
    m_flipMap->setChecked(shown);
}

void CompareView::showFlipMap() {
    ImageCanvas* canvas = m_context.viewer->canvas();
    const QImage& map = m_measurement.flipMap;
    if (m_flipMap->isChecked() && m_measurement.haveReference && !map.isNull()) {
        canvas->setOverlay(map);
        m_flipMapOnCanvas = true;
    } else if (m_flipMapOnCanvas) {
        canvas->clearOverlay();
        m_flipMapOnCanvas = false;
    }
}

void CompareView::show() {
    const Measurement& m = m_measurement;
    const bool stale = metricsStale();
    // Columns: raw, result, raw in the region, result in the region; rows: SSIM, relMSE, PSNR,
    // FLIP.
    const Metrics result{m.ssimImage, m.relMseImage, m.psnrImage, m.flipImage};
    const Metrics resultRegion{m.ssimRegion, m.relMseRegion, m.psnrRegion, m.flipRegion};
    const Metrics* columns[] = {&m.rawImage, &result, &m.rawRegion, &resultRegion};
    for (int col = 0; col < 4; ++col) {
        const bool have = m.haveReference && (col % 2 == 1 || m.haveRaw);
        const Metrics& x = *columns[col];
        const double values[] = {x.ssim, x.relMse, x.psnr, x.flip};
        // SSIM lives near 1: four decimals tell results apart; the others to three digits.
        const QString texts[] = {QString::number(x.ssim, 'f', 4), compactNumber(x.relMse),
                                 compactNumber(x.psnr), compactNumber(x.flip)};
        for (int row = 0; row < 4; ++row) {
            auto* item = new QTableWidgetItem(!have || std::isnan(values[row]) ? QStringLiteral("–")
                                              : stale                          ? tr("stale")
                                                                               : texts[row]);
            item->setTextAlignment(Qt::AlignCenter);
            // A stale figure is kept out of sight, in the tooltip (it compares other scenes).
            if (have && stale) {
                item->setForeground(QColor(150, 150, 150));
                item->setToolTip(tr("%1 against a reference of another scene, look or camera")
                                     .arg(values[row], 0, 'g', 4));
            }
            m_table->setItem(tableRow(row, col), col % 2, item);
        }
    }
    // Did denoising help? The result's relMSE against the raw render's.
    QString verdict;
    if (m.haveReference && m.haveRaw && !stale && m.relMseImage > 0.0 && m.rawImage.relMse > 0.0) {
        const double ratio = m.rawImage.relMse / m.relMseImage;
        verdict = ratio >= 1.0
                      ? tr("Denoising helped: relMSE %1× lower than the raw render's (image), "
                           "SSIM %2 → %3.")
                      : tr("Denoising made it worse: relMSE %1× the raw render's (image), "
                           "SSIM %2 → %3.");
        verdict = verdict.arg(ratio >= 1.0 ? ratio : 1.0 / ratio, 0, 'g', 2)
                      .arg(m.rawImage.ssim, 0, 'f', 3)
                      .arg(m.ssimImage, 0, 'f', 3);
    }
    m_verdict->setText(verdict);
    m_verdict->setVisible(!verdict.isEmpty());
    if (!std::isfinite(m.min[0])) {
        m_stats->setText(tr("Region statistics appear once there is an image."));
        return;
    }
    QString text = tr("Region, per channel (R G B):");
    const char* names[] = {"min", "mean", "max"};
    const std::array<double, 3>* rows[] = {&m.min, &m.mean, &m.max};
    for (int r = 0; r < 3; ++r)
        text += QStringLiteral("\n%1  %2  %3  %4")
                    .arg(QString::fromLatin1(names[r]), -5)
                    .arg((*rows[r])[0], 0, 'g', 4)
                    .arg((*rows[r])[1], 0, 'g', 4)
                    .arg((*rows[r])[2], 0, 'g', 4);
    m_stats->setText(text);
}

}  // namespace glint::studio
