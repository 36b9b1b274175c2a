#include "views/compare_view.h"

#include <QComboBox>
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

#include "glint/image/metrics.h"
#include "model/render_eta.h"

namespace glint::studio {

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
    m_table = new QTableWidget(2, 3, this);
    m_table->setHorizontalHeaderLabels({tr("SSIM"), tr("relMSE"), tr("PSNR (dB)")});
    m_table->setVerticalHeaderLabels({tr("Image"), tr("Region")});
    m_table->setEditTriggers(QAbstractItemView::NoEditTriggers);
    m_table->horizontalHeader()->setSectionResizeMode(QHeaderView::Stretch);
    m_table->setVerticalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    m_table->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
    m_table->resizeRowsToContents();
    // As tall as its header and two rows as they are (no blank band under them: at 1366×768
    // every pixel of the panel counts).
    m_table->setFixedHeight(m_table->horizontalHeader()->sizeHint().height() +
                            m_table->rowHeight(0) + m_table->rowHeight(1) +
                            2 * m_table->frameWidth());
    m_table->setToolTip(
        tr("Of the result (the composite) against the reference; the region's "
           "figures cover its bounding box"));
    m_lookWarning =
        new QLabel(tr("The reference was rendered with another look or camera: its metrics compare "
                      "different scenes. Render it again."),
                   this);
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
    auto* axis = new QComboBox(this);
    axis->addItem(tr("relMSE vs seconds"));
    axis->addItem(tr("relMSE vs spp"));
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
    layout->addWidget(m_lookWarning);
    layout->addWidget(m_error);
    layout->addWidget(m_table);
    layout->addWidget(m_stats);
    layout->addWidget(axis);
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
    connect(axis, &QComboBox::currentIndexChanged, this,
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

void CompareView::updateLookWarning() {
    const bool differs = m_context.document->referenceLookDiffers();
    m_lookWarning->setVisible(differs);
    if (differs && !m_warnedLook) emit status(m_lookWarning->text());
    m_warnedLook = differs;
}

void CompareView::schedule() {
    m_debounce.start();
}

void CompareView::measure() {
    const Image* result = m_context.viewer->resultImage();
    if (!result) return;
    FramePtr reference = m_context.document->reference();
    const Rect rect = m_context.region->bounds(result->width(), result->height());
    auto image = std::make_shared<const Image>(*result);
    auto mask =
        std::make_shared<const Image>(m_context.region->mask(result->width(), result->height()));
    m_tasks.run<Measurement>(
        QStringLiteral("measure"),
        [image, reference, rect, mask](const TaskRunner::CancelFlag&) {
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
            }
            return m;
        },
        [this](Measurement m) {
            m_measurement = m;
            show();
            emit measured();
        });
}

void CompareView::show() {
    const Measurement& m = m_measurement;
    auto cell = [&](int row, int col, double v, int digits) {
        auto* item = new QTableWidgetItem(m.haveReference ? QString::number(v, 'f', digits)
                                                          : QStringLiteral("–"));
        item->setTextAlignment(Qt::AlignCenter);
        m_table->setItem(row, col, item);
    };
    cell(0, 0, m.ssimImage, 4);
    cell(0, 1, m.relMseImage, 5);
    cell(0, 2, m.psnrImage, 2);
    cell(1, 0, m.ssimRegion, 4);
    cell(1, 1, m.relMseRegion, 5);
    cell(1, 2, m.psnrRegion, 2);
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
