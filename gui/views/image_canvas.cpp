#include "views/image_canvas.h"

#include "views/canvas_overlays.h"
#include "views/text_editing.h"

#include <QApplication>
#include <QMouseEvent>
#include <QPainter>
#include <QWheelEvent>

#include <tuple>

#include <algorithm>
#include <cmath>

namespace glint::studio {

ImageCanvas::ImageCanvas(QWidget* parent) : QWidget(parent) {
    setMouseTracking(true);
    // Tab gives focus; a click gives it in mousePressEvent, which can then tell a click that only
    // focuses the canvas from one that paints.
    setFocusPolicy(Qt::TabFocus);
    setMinimumSize(200, 150);
    setAttribute(Qt::WA_OpaquePaintEvent);
}

void ImageCanvas::setImage(const Image& image) {
    m_lastImage = std::make_shared<Image>(image);
    // A small image converts at once; a large one (tens of ms at 1024²) on a worker, the image
    // shown until then being the previous one (or none).
    if (std::size_t(image.width()) * std::size_t(image.height()) > kSyncPixels) {
        convertInBackground();
        return;
    }
    m_tasks.cancel(QStringLiteral("convert"));
    m_converting = false;
    m_dirty.clear();
    const bool resized = m_image.width() != image.width() || m_image.height() != image.height();
    updateAutoRange();
    m_image = toQImage(image, m_display);
    if (resized || m_fitted) fit();
    update();
    emit imageShown();
}

void ImageCanvas::updateAutoRange() {
    if (m_display.mode != DisplayMode::FalseColor) return;
    if (!m_display.autoRange) {
        m_display.falseLo = 0.0f;
        m_display.falseHi = 1.0f;
        return;
    }
    if (m_lastImage->empty()) return;
    const std::pair<float, float> before{m_display.falseLo, m_display.falseHi};
    std::tie(m_display.falseLo, m_display.falseHi) = luminancePercentiles(*m_lastImage, m_display);
    // The compare image is shown with A's range, for a like-for-like comparison.
    if (!m_compareSource.empty() && falseColorRange() != before)
        m_compare = toQImage(m_compareSource, m_display);
}

void ImageCanvas::convertInBackground() {
    // The worker reads the linear image; a dab meanwhile writes to a copy (updateImage).
    std::shared_ptr<const Image> source = m_lastImage;
    updateAutoRange();
    const DisplaySettings display = m_display;
    m_converting = true;
    m_dirty.clear();
    m_tasks.run<QImage>(
        QStringLiteral("convert"),
        [source, display](const TaskRunner::CancelFlag&) { return toQImage(*source, display); },
        [this, display](QImage converted) {
            m_converting = false;
            if (!(display == m_display) || converted.width() != m_lastImage->width() ||
                converted.height() != m_lastImage->height()) {
                convertInBackground();  // the display changed meanwhile
                return;
            }
            const bool resized = m_image.size() != converted.size();
            m_image = std::move(converted);
            // Dabs that came meanwhile are in the linear image only.
            for (const Rect& r : m_dirty) convertRect(m_image, *m_lastImage, m_display, r);
            m_dirty.clear();
            if (resized || m_fitted) fit();
            update();
            emit imageShown();
        });
}

void ImageCanvas::updateImage(const Image& image, const Rect& rect) {
    if (m_lastImage->width() != image.width() || m_lastImage->height() != image.height() ||
        (m_image.isNull() && !m_converting)) {
        setImage(image);
        return;
    }
    const Rect r = intersect(rect, image.bounds());
    if (m_lastImage.use_count() > 1) m_lastImage = std::make_shared<Image>(*m_lastImage);
    for (int y = r.y0; y < r.y1; ++y)
        std::copy(image.row(y) + std::size_t(r.x0) * image.channels(),
                  image.row(y) + std::size_t(r.x1) * image.channels(),
                  m_lastImage->row(y) + std::size_t(r.x0) * image.channels());
    // While a conversion runs, the image shown may be another one (or of another size).
    if (m_image.width() == image.width() && m_image.height() == image.height())
        convertRect(m_image, image, m_display, r);
    if (m_converting) m_dirty.push_back(r);
    updateImageRect(r);
}

void ImageCanvas::updateImageRect(const Rect& r) {
    const QRectF w(toWidget(QPointF(r.x0, r.y0)), toWidget(QPointF(r.x1, r.y1)));
    update(w.toAlignedRect().adjusted(-2, -2, 2, 2));
}

void ImageCanvas::setCompareImage(const Image* image) {
    m_compareSource = image ? *image : Image();
    m_compare = image ? toQImage(*image, m_display) : QImage();
    update();
}

void ImageCanvas::setFlipped(bool flipped) {
    m_flipped = flipped;
    update();
}

void ImageCanvas::setWipe(std::optional<double> fraction) {
    m_wipe = fraction ? std::optional<double>(std::clamp(*fraction, 0.0, 1.0)) : std::nullopt;
    update();
}

bool ImageCanvas::showsWipe() const {
    return m_wipe && !m_flipped && !m_compare.isNull() && m_compare.size() == m_image.size();
}

std::optional<double> ImageCanvas::wipeLineX() const {
    if (!showsWipe()) return std::nullopt;
    return toWidget(QPointF(*m_wipe * m_image.width(), 0)).x();
}

void ImageCanvas::setLabel(const QString& text) {
    if (text == m_label) return;
    m_label = text;
    update();
}

QStringList ImageCanvas::legendLabels() const {
    return glint::studio::legendLabels(m_display.falseLo, m_display.falseHi);
}

void ImageCanvas::setDisplay(const DisplaySettings& given) {
    // An automatic range is the canvas's own: only the other settings can differ.
    DisplaySettings display = given;
    if (display.autoRange && m_display.autoRange) {
        display.falseLo = m_display.falseLo;
        display.falseHi = m_display.falseHi;
    }
    if (display == m_display) return;
    m_display = display;
    updateAutoRange();
    if (!m_lastImage->empty()) m_image = toQImage(*m_lastImage, m_display);
    if (!m_compareSource.empty()) m_compare = toQImage(m_compareSource, m_display);
    if (!m_brushSourceImage.empty()) m_brushSource = toQImage(m_brushSourceImage, m_display);
    update();
    emit displayChanged();
}

void ImageCanvas::setTool(Tool tool) {
    const bool changed = tool != m_tool;
    m_tool = tool;
    m_drawing.clear();
    setCursor(toolCursor());
    update();
    if (changed) emit toolChanged(tool);
}

Qt::CursorShape ImageCanvas::toolCursor() const {
    return m_tool == Tool::Pan     ? Qt::OpenHandCursor
           : m_tool == Tool::Brush ? Qt::BlankCursor
                                   : Qt::CrossCursor;
}

void ImageCanvas::setRegion(const QPolygonF& polygon) {
    m_region = polygon;
    m_regionPath = QPainterPath();
    if (!polygon.isEmpty()) {
        m_regionPath.addPolygon(polygon);
        m_regionPath.closeSubpath();
    }
    update();
}

void ImageCanvas::setPreview(const Image& preview, const Rect& rect) {
    m_preview = toQImage(preview, m_display);
    m_previewRect = rect;
    update();
}

void ImageCanvas::clearPreview() {
    if (m_preview.isNull()) return;
    m_preview = QImage();
    update();
}

void ImageCanvas::setOverlay(const QImage& overlay) {
    m_overlay = overlay;
    update();
}

void ImageCanvas::clearOverlay() {
    if (m_overlay.isNull() && m_legend.isEmpty()) return;
    m_overlay = QImage();
    m_legend.clear();
    update();
}

void ImageCanvas::setSelection(const QImage& selection) {
    if (m_selection.isNull() && selection.isNull()) return;
    m_selection = selection;
    update();
}

void ImageCanvas::setLegend(const QList<QPair<QColor, QString>>& entries) {
    m_legend = entries;
    update();
}

void ImageCanvas::setBrush(double size, double softness) {
    m_brushSize = size;
    m_brushSoftness = softness;
    update();
}

void ImageCanvas::setBrushSource(const Image* source) {
    m_brushSourceImage = source ? *source : Image();
    m_brushSource = source ? toQImage(*source, m_display) : QImage();
    update();
}

void ImageCanvas::setBrushSource(Image source, QImage converted) {
    m_brushSourceImage = std::move(source);
    m_brushSource = std::move(converted);
    update();
}

void ImageCanvas::fit() {
    m_fitted = true;
    if (m_image.isNull() || width() <= 0 || height() <= 0) return;
    m_zoom = std::min(double(width()) / m_image.width(), double(height()) / m_image.height());
    m_offset = QPointF((width() - m_image.width() * m_zoom) / 2.0,
                       (height() - m_image.height() * m_zoom) / 2.0);
    update();
}

void ImageCanvas::oneToOne() {
    m_fitted = false;
    const QPointF centre = toImage(QPointF(width() / 2.0, height() / 2.0));
    m_zoom = 1.0;
    m_offset = QPointF(width() / 2.0, height() / 2.0) - centre;
    update();
}

void ImageCanvas::zoomBy(double factor, const QPointF& anchor) {
    m_fitted = false;
    const QPointF at = toImage(anchor);
    m_zoom = std::clamp(m_zoom * factor, 1.0 / 64.0, 64.0);
    m_offset = anchor - at * m_zoom;
    update();
}

QPointF ImageCanvas::toImage(const QPointF& p) const {
    return (p - m_offset) / m_zoom;
}

QPointF ImageCanvas::toWidget(const QPointF& imagePoint) const {
    return imagePoint * m_zoom + m_offset;
}

QRectF ImageCanvas::imageRectInWidget() const {
    return QRectF(m_offset, QSizeF(m_image.width() * m_zoom, m_image.height() * m_zoom));
}

void ImageCanvas::drawImage(QPainter& p, const QImage& image, const QRectF& clip) {
    // Only the visible part of the image is scaled (nearest neighbour: pixels stay pixels).
    const QRectF visible = clip.intersected(imageRectInWidget());
    if (visible.isEmpty()) return;
    const QPointF a = toImage(visible.topLeft()), b = toImage(visible.bottomRight());
    const int x0 = std::max(0, int(std::floor(a.x()))), y0 = std::max(0, int(std::floor(a.y())));
    const int x1 = std::min(image.width(), int(std::ceil(b.x()))),
              y1 = std::min(image.height(), int(std::ceil(b.y())));
    if (x1 <= x0 || y1 <= y0) return;
    const QRectF target(toWidget(QPointF(x0, y0)), toWidget(QPointF(x1, y1)));
    p.drawImage(target, image, QRectF(x0, y0, x1 - x0, y1 - y0));
}

void ImageCanvas::paintEvent(QPaintEvent* event) {
    QPainter p(this);
    p.fillRect(event->rect(), QColor(48, 48, 48));
    if (m_image.isNull()) {
        p.setPen(QColor(170, 170, 170));
        p.drawText(rect(), Qt::AlignCenter,
                   tr("Open a scene.json, a layered EXR or a session (Ctrl+O), or drop one here"));
        return;
    }
    p.setRenderHint(QPainter::SmoothPixmapTransform, false);
    const QRectF clip = QRectF(event->rect());
    const bool haveB = !m_compare.isNull() && m_compare.size() == m_image.size();
    if (haveB && m_flipped) {
        drawImage(p, m_compare, clip);
    } else if (showsWipe()) {
        // A left of the wipe line, B right of it.
        const double xw = *wipeLineX();
        drawImage(
            p, m_image,
            clip.intersected(QRectF(clip.left(), clip.top(), xw - clip.left(), clip.height())));
        drawImage(p, m_compare,
                  clip.intersected(QRectF(xw, clip.top(), clip.right() - xw, clip.height())));
        // The line, dark-edged for light images, with a handle to drag at mid-height.
        p.setPen(QPen(QColor(0, 0, 0, 160), 3));
        p.drawLine(QPointF(xw, 0), QPointF(xw, height()));
        p.setPen(QPen(QColor(255, 255, 255, 230), 1));
        p.drawLine(QPointF(xw, 0), QPointF(xw, height()));
        p.fillRect(QRectF(xw - 3, height() / 2.0 - 12, 7, 24), QColor(255, 255, 255, 230));
        p.drawText(QPointF(xw - 18, height() - 10), QStringLiteral("A"));
        p.drawText(QPointF(xw + 8, height() - 10), QStringLiteral("B"));
    } else {
        drawImage(p, m_image, clip);
    }
    if (!m_preview.isNull()) {
        // The preview shows inside the region only.
        p.save();
        if (!m_regionPath.isEmpty()) {
            QTransform t;
            t.translate(m_offset.x(), m_offset.y());
            t.scale(m_zoom, m_zoom);
            p.setClipPath(t.map(m_regionPath));
        }
        const QRectF target(toWidget(QPointF(m_previewRect.x0, m_previewRect.y0)),
                            toWidget(QPointF(m_previewRect.x1, m_previewRect.y1)));
        p.drawImage(target, m_preview);
        p.restore();
    }
    if (!m_overlay.isNull()) p.drawImage(imageRectInWidget(), m_overlay);
    if (!m_selection.isNull()) p.drawImage(imageRectInWidget(), m_selection);
    // The region of interest: a dashed outline, white over black for any background.
    auto outline = [&](const QPolygonF& poly, bool closed) {
        QPolygonF w;
        for (const QPointF& q : poly) w << toWidget(q);
        p.setRenderHint(QPainter::Antialiasing, true);
        p.setPen(QPen(Qt::black, 1.5));
        closed ? p.drawPolygon(w) : p.drawPolyline(w);
        p.setPen(QPen(Qt::white, 1.5, Qt::DashLine));
        closed ? p.drawPolygon(w) : p.drawPolyline(w);
        p.setRenderHint(QPainter::Antialiasing, false);
    };
    if (!m_region.isEmpty()) outline(m_region, true);
    if (!m_drawing.isEmpty())
        outline(m_drawing, m_tool == Tool::Rectangle || m_tool == Tool::RenderRegion);
    // The brush: what it would paint inside, and its inner and outer radii.
    if (m_tool == Tool::Brush && m_cursor) {
        const double r = m_brushSize / 2.0 * m_zoom;
        p.setRenderHint(QPainter::Antialiasing, true);
        if (!m_brushSource.isNull() && m_brushSource.size() == m_image.size()) {
            p.save();
            QPainterPath circle;
            circle.addEllipse(*m_cursor, r, r);
            p.setClipPath(circle);
            drawImage(p, m_brushSource, circle.boundingRect());
            p.restore();
        }
        p.setBrush(Qt::NoBrush);
        p.setPen(QPen(Qt::black, 2.0));
        p.drawEllipse(*m_cursor, r, r);
        p.setPen(QPen(Qt::white, 1.0));
        p.drawEllipse(*m_cursor, r, r);
        if (m_brushSoftness > 0.0 && m_brushSoftness < 1.0) {
            p.setPen(QPen(QColor(255, 255, 255, 140), 1.0, Qt::DotLine));
            p.drawEllipse(*m_cursor, r * m_brushSoftness, r * m_brushSoftness);
        }
    }
    // A preview (a tuned filter, a hovered bank member) covers the region: say so.
    drawCanvasLabel(p, rect(),
                    m_preview.isNull() || m_label.isEmpty()
                        ? m_label
                        : tr("%1 · preview inside the region").arg(m_label));
    if (m_display.mode == DisplayMode::FalseColor)
        drawFalseColorLegend(p, rect(), m_display.falseLo, m_display.falseHi);
    if (!m_legend.isEmpty()) drawCategoryLegend(p, rect(), m_legend);
    emit painted();
}

void ImageCanvas::resizeEvent(QResizeEvent*) {
    if (m_fitted) fit();
}

void ImageCanvas::wheelEvent(QWheelEvent* event) {
    const double steps = event->angleDelta().y() / 120.0;
    zoomBy(std::pow(1.25, steps), event->position());
}

void ImageCanvas::mousePressEvent(QMouseEvent* event) {
    // A left press near the wipe line drags it, whatever the tool.
    if (const std::optional<double> xw = wipeLineX();
        xw && event->button() == Qt::LeftButton && std::abs(event->position().x() - *xw) <= 6.0) {
        if (!hasFocus()) setFocus(Qt::MouseFocusReason);
        m_wipeDragging = true;
        setCursor(Qt::SplitHCursor);
        return;
    }
    // A click into a canvas without focus focuses it. Out of a field being typed in, with the
    // brush or the wand, it does not also paint (the user clicked to get the keys back). Out of
    // a button, a list or a drop-down (a side panel's "Paint with it", the layer list) it paints:
    // single keys reach the canvas from there anyway, and the press is the stroke's start.
    if (!hasFocus() && window()->isActiveWindow()) {
        const bool typing = isTextEditing(QApplication::focusWidget());
        setFocus(Qt::MouseFocusReason);
        if (typing && (m_tool == Tool::Brush || m_tool == Tool::Wand)) {
            m_focusClick = true;
            return;
        }
    }
    const QPointF at = toImage(event->position());
    m_pressWidget = event->position();
    m_pressOffset = m_offset;
    const bool middle = event->button() == Qt::MiddleButton;
    if (middle || m_tool == Tool::Pan) {
        m_panning = true;
        setCursor(Qt::ClosedHandCursor);
        return;
    }
    if (m_tool == Tool::Brush) {
        if (event->modifiers() & Qt::ShiftModifier) {
            m_resizingBrush = true;
            m_pressBrushSize = m_brushSize;
            return;
        }
        m_stroking = true;
        emit strokeBegan(at, event->button() == Qt::RightButton);
        return;
    }
    if (m_tool == Tool::Wand) {
        if (at.x() >= 0 && at.y() >= 0 && at.x() < m_image.width() && at.y() < m_image.height())
            emit wandClicked(QPoint(int(at.x()), int(at.y())), event->button() == Qt::RightButton);
        return;
    }
    if (event->button() == Qt::LeftButton) {
        m_anchor = at;
        m_drawing = QPolygonF() << at;
    }
}

void ImageCanvas::mouseMoveEvent(QMouseEvent* event) {
    const QPointF at = toImage(event->position());
    const std::optional<QPointF> previous = m_cursor;
    m_cursor = event->position();
    if (at.x() >= 0 && at.y() >= 0 && at.x() < m_image.width() && at.y() < m_image.height())
        emit hovered(int(at.x()), int(at.y()));
    else
        emit hovered(-1, -1);
    if (event->buttons() == Qt::NoButton) {
        // Over the wipe line the cursor says it can be dragged.
        const std::optional<double> xw = wipeLineX();
        const bool near = xw && std::abs(event->position().x() - *xw) <= 6.0;
        setCursor(near ? Qt::SplitHCursor : toolCursor());
    }
    if (m_wipeDragging) {
        m_wipe = std::clamp(at.x() / std::max(1, m_image.width()), 0.0, 1.0);
        update();
        emit wipeMoved(*m_wipe);
        return;
    }
    if (m_panning) {
        m_fitted = false;
        m_offset = m_pressOffset + (event->position() - m_pressWidget);
        update();
        return;
    }
    if (m_resizingBrush) {
        const double dx = event->position().x() - m_pressWidget.x();
        m_brushSize = std::clamp(m_pressBrushSize * std::pow(2.0, dx / 100.0), 1.0, 2048.0);
        emit brushResized(m_brushSize);
        update();
        return;
    }
    if (m_stroking) emit strokeMoved(at);
    if (!m_drawing.isEmpty() && (event->buttons() & Qt::LeftButton)) {
        if (m_tool == Tool::Rectangle || m_tool == Tool::RenderRegion) {
            m_drawing = QPolygonF(QRectF(m_anchor, at).normalized());
        } else {
            m_drawing << at;
        }
        update();
    }
    if (m_tool == Tool::Brush) {
        // Repaint where the brush was and where it is.
        const double r = m_brushSize / 2.0 * m_zoom + 3.0;
        QRectF dirty(event->position() - QPointF(r, r), QSizeF(2 * r, 2 * r));
        if (previous) dirty = dirty.united(QRectF(*previous - QPointF(r, r), QSizeF(2 * r, 2 * r)));
        update(dirty.toAlignedRect());
    }
}

void ImageCanvas::mouseReleaseEvent(QMouseEvent* event) {
    if (m_focusClick) {
        m_focusClick = false;
        return;
    }
    if (m_wipeDragging) {
        m_wipeDragging = false;
        setCursor(toolCursor());
        return;
    }
    if (m_panning) {
        m_panning = false;
        setCursor(m_tool == Tool::Pan ? Qt::OpenHandCursor : Qt::CrossCursor);
        return;
    }
    if (m_resizingBrush) {
        m_resizingBrush = false;
        return;
    }
    if (m_stroking) {
        m_stroking = false;
        emit strokeEnded();
        return;
    }
    if (m_drawing.isEmpty()) return;
    const QPolygonF drawn = m_drawing;
    m_drawing.clear();
    update();
    const QRectF bounds = drawn.boundingRect();
    if (bounds.width() < 2.0 || bounds.height() < 2.0) return;  // a click, not a region
    if (m_tool == Tool::Rectangle || m_tool == Tool::RenderRegion) {
        const QRect r = QRectF(std::floor(bounds.left()), std::floor(bounds.top()),
                               std::ceil(bounds.right()) - std::floor(bounds.left()),
                               std::ceil(bounds.bottom()) - std::floor(bounds.top()))
                            .toRect()
                            .intersected(QRect(0, 0, m_image.width(), m_image.height()));
        if (r.isEmpty()) return;
        if (m_tool == Tool::RenderRegion)
            emit renderRegionDrawn(r);
        else
            emit rectangleDrawn(r);
    } else if (m_tool == Tool::Lasso && drawn.size() >= 3) {
        emit lassoDrawn(drawn);
    }
    (void)event;
}

void ImageCanvas::leaveEvent(QEvent*) {
    m_cursor.reset();
    emit hovered(-1, -1);
    update();
}

}  // namespace glint::studio
