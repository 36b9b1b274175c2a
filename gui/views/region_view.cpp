#include "views/region_view.h"

#include <QLabel>
#include <QPushButton>
#include <QToolButton>
#include <QVBoxLayout>

namespace glint::studio {

RegionView::RegionView(const StudioContext& context, QWidget* parent) : StageView(context, parent) {
    m_lasso = new QToolButton(this);
    m_lasso->setText(tr("Lasso"));
    m_lasso->setCheckable(true);
    m_lasso->setChecked(true);
    m_lasso->setToolTip(tr("Draw the region free-hand with the left button (L)"));
    m_rectangle = new QToolButton(this);
    m_rectangle->setText(tr("Rectangle"));
    m_rectangle->setCheckable(true);
    m_rectangle->setToolTip(tr("Drag a rectangle"));
    addToolButton(m_lasso, ImageCanvas::Tool::Lasso);
    addToolButton(m_rectangle, ImageCanvas::Tool::Rectangle);
    auto* whole = new QPushButton(tr("Whole image"), this);
    whole->setToolTip(tr("Work on the whole image (W)"));
    m_label = new QLabel(this);
    m_label->setWordWrap(true);
    auto* hint = new QLabel(tr("Select the part of the image to work on next. Then choose a filter "
                               "for it (stage 3) and paint it in (stage 4); come back here for the "
                               "next region."),
                            this);
    hint->setWordWrap(true);
    auto* tools = new QHBoxLayout;
    tools->addWidget(m_lasso);
    tools->addWidget(m_rectangle);
    tools->addWidget(whole);
    tools->addStretch(1);
    auto* layout = new QVBoxLayout(this);
    layout->addWidget(hint);
    layout->addLayout(tools);
    layout->addWidget(m_label);
    layout->addStretch(1);

    ImageCanvas* canvas = m_context.viewer->canvas();
    connect(whole, &QPushButton::clicked, m_context.region, &RegionOfInterest::clear);
    connect(canvas, &ImageCanvas::lassoDrawn, this, [this](const QPolygonF& polygon) {
        if (active()) m_context.region->setPolygon(polygon);
    });
    connect(canvas, &ImageCanvas::rectangleDrawn, this, [this](const QRect& r) {
        if (!active() || !m_rectangle->isChecked()) return;
        m_context.region->setPolygon(QPolygonF(QRectF(r)));
    });
    connect(m_context.region, &RegionOfInterest::changed, this, &RegionView::updateLabel);
    connect(m_context.document, &Document::frameChanged, this, &RegionView::updateLabel);
    updateLabel();
}

void RegionView::activate() {
    applyTool();
}

void RegionView::deactivate() {}

void RegionView::updateLabel() {
    FramePtr frame = m_context.document->frame();
    if (!frame) {
        m_label->setText(tr("No image yet."));
        return;
    }
    const Rect r = m_context.region->bounds(frame->width(), frame->height());
    if (m_context.region->wholeImage()) {
        m_label->setText(tr("Region: the whole image (%1×%2).").arg(r.width()).arg(r.height()));
        return;
    }
    m_label->setText(tr("Region: %1 pixels inside a %2×%3 box at (%4, %5).")
                         .arg(m_context.region->pixelCount(frame->width(), frame->height()))
                         .arg(r.width())
                         .arg(r.height())
                         .arg(r.x0)
                         .arg(r.y0));
}

}  // namespace glint::studio
