// The image canvas: draws a converted image with QPainter (zoom to the cursor, pan, fit, 1:1),
// an optional second image for A/B flip and wipe, the region of interest, a preview inside it,
// translucent overlays and the brush. Mouse input becomes image-space signals for the stage
// that owns the current tool. It knows nothing of sessions or renders.
#pragma once

#include <QColor>
#include <QImage>
#include <QList>
#include <QPainterPath>
#include <QPair>
#include <QPointF>
#include <QPolygonF>
#include <QString>
#include <QStringList>
#include <QWidget>

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "glint/image/image.h"
#include "model/task_runner.h"
#include "views/display.h"

namespace glint::studio {

class ImageCanvas : public QWidget {
    Q_OBJECT
  public:
    /// What a left drag does. RenderRegion draws a rectangle like Rectangle but reports it as
    /// renderRegionDrawn (the render bar's one-shot tool), never as a region of interest.
    enum class Tool { Pan, Lasso, Rectangle, Brush, Wand, RenderRegion };

    explicit ImageCanvas(QWidget* parent = nullptr);

    /// Shows `image` (linear) with the display settings.
    void setImage(const Image& image);
    /// Re-converts only `rect` of `image` (same size as shown): a dab's worth of pixels.
    void updateImage(const Image& image, const Rect& rect);
    bool hasImage() const { return !m_image.isNull(); }
    QSize imageSize() const { return m_image.size(); }
    /// The displayed image (for screenshots and tests).
    const QImage& shownImage() const { return m_image; }

    /// The B image of A/B comparisons (nothing: no comparison). Copied.
    void setCompareImage(const Image* image);
    /// Shows B instead of A (the flip key).
    void setFlipped(bool flipped);
    bool flipped() const { return m_flipped; }
    /// A wipe at this fraction of the image width (A left of it, B right); nothing: off. With
    /// a B image, a left drag starting near the line moves it (any tool), as in Nuke and tev.
    void setWipe(std::optional<double> fraction);
    std::optional<double> wipe() const { return m_wipe; }
    /// The widget x of the wipe line (nothing: no wipe shown).
    std::optional<double> wipeLineX() const;

    /// The text drawn in the top-left corner saying what is shown (empty: none).
    void setLabel(const QString& text);
    const QString& label() const { return m_label; }
    /// The false-colour range in use (automatic or fixed) and the numbers its legend shows.
    std::pair<float, float> falseColorRange() const {
        return {m_display.falseLo, m_display.falseHi};
    }
    QStringList legendLabels() const;

    void setDisplay(const DisplaySettings& display);
    const DisplaySettings& display() const { return m_display; }

    /// The one place the active tool is set; emits toolChanged so panels show it.
    void setTool(Tool tool);
    Tool tool() const { return m_tool; }

    /// The region of interest as a polygon in image pixels (empty: the whole image).
    void setRegion(const QPolygonF& polygon);
    /// A preview (linear, 3 channels) shown over `rect`, clipped to the region polygon.
    void setPreview(const Image& preview, const Rect& rect);
    void clearPreview();
    /// A translucent overlay over the whole image (change map, filter variance...).
    void setOverlay(const QImage& overlay);
    /// True while an overlay is shown.
    bool hasOverlay() const { return !m_overlay.isNull(); }
    void clearOverlay();
    /// A selection drawn over the overlay (the magic wand's: selectionOverlay); null clears.
    void setSelection(const QImage& selection);
    bool hasSelection() const { return !m_selection.isNull(); }
    /// Entries of a categorical map's legend (a colour and its name), drawn bottom left; empty:
    /// none.
    void setLegend(const QList<QPair<QColor, QString>>& entries);
    const QList<QPair<QColor, QString>>& legend() const { return m_legend; }

    /// Brush outline and, when given, what the brush would paint (linear, frame-sized): shown
    /// inside the brush under the cursor. Copied.
    void setBrush(double size, double softness);
    void setBrushSource(const Image* source);
    /// The same with the conversion done elsewhere (`converted` with display()).
    void setBrushSource(Image source, QImage converted);
    double brushSize() const { return m_brushSize; }

    /// View transform.
    void fit();
    void oneToOne();
    void zoomBy(double factor, const QPointF& anchor);
    double zoom() const { return m_zoom; }
    /// Image position (pixels, continuous) under widget point `p`.
    QPointF toImage(const QPointF& p) const;
    QPointF toWidget(const QPointF& imagePoint) const;

  signals:
    /// The pixel under the cursor (x or y < 0 when outside the image).
    void hovered(int x, int y);
    void lassoDrawn(const QPolygonF& polygon);
    void rectangleDrawn(const QRect& rect);
    /// A rectangle drawn with the RenderRegion tool.
    void renderRegionDrawn(const QRect& rect);
    /// setDisplay changed how values reach the screen.
    void displayChanged();
    /// setTool changed the tool.
    void toolChanged(glint::studio::ImageCanvas::Tool tool);
    void strokeBegan(const QPointF& at, bool subtract);
    void strokeMoved(const QPointF& at);
    void strokeEnded();
    void wandClicked(const QPoint& pixel, bool subtract);
    /// Shift+drag with the brush tool resized it.
    void brushResized(double size);
    /// A frame was painted on screen (instrumentation of the speed test).
    void painted();
    /// A new image replaced the one shown (shownImage() has it).
    void imageShown();
    /// The user dragged the wipe line to this fraction of the image width.
    void wipeMoved(double fraction);

  protected:
    void paintEvent(QPaintEvent* event) override;
    void resizeEvent(QResizeEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void leaveEvent(QEvent* event) override;

  private:
    void drawImage(QPainter& p, const QImage& image, const QRectF& clip);
    void updateImageRect(const Rect& rect);
    QRectF imageRectInWidget() const;
    bool showsWipe() const;
    Qt::CursorShape toolCursor() const;
    /// Sets the false-colour range of m_display from m_lastImage when it is automatic.
    void updateAutoRange();

    // Images larger than this convert for the screen on a worker (about 2 ms on the UI thread).
    static constexpr std::size_t kSyncPixels = 256 * 256;
    void convertInBackground();
    TaskRunner m_tasks;
    bool m_converting = false;  // a conversion of m_lastImage runs
    std::vector<Rect> m_dirty;  // rectangles dabbed meanwhile, converted again when it lands
    QImage m_image;
    QImage m_compare;
    QImage m_preview;
    Rect m_previewRect{};
    QImage m_overlay;
    QImage m_selection;
    QList<QPair<QColor, QString>> m_legend;
    QImage m_brushSource;
    // The linear image shown, for re-conversion when the display changes (shared with the
    // conversion running, if any).
    std::shared_ptr<Image> m_lastImage = std::make_shared<Image>();
    Image m_compareSource;  // copies, for re-conversion when the display changes
    Image m_brushSourceImage;
    DisplaySettings m_display;
    bool m_flipped = false;
    std::optional<double> m_wipe;
    bool m_wipeDragging = false;
    QString m_label;
    Tool m_tool = Tool::Pan;
    QPolygonF m_region;
    QPainterPath m_regionPath;
    double m_brushSize = 48.0;
    double m_brushSoftness = 0.5;

    double m_zoom = 1.0;
    QPointF m_offset;  // widget position of image pixel (0, 0)
    bool m_fitted = true;

    // Interaction state.
    bool m_panning = false;
    bool m_stroking = false;
    bool m_resizingBrush = false;
    bool m_focusClick = false;  // the press only took the keys from a field: it does not paint
    QPointF m_pressWidget;
    QPointF m_pressOffset;
    double m_pressBrushSize = 0.0;
    QPolygonF m_drawing;              // lasso or rectangle being drawn (image coordinates)
    QPointF m_anchor;                 // where the rectangle started
    std::optional<QPointF> m_cursor;  // widget position of the cursor
};

}  // namespace glint::studio
