// Stage 4, painting: the palette of layers chosen so far, a soft brush (size and softness; [ and ]
// or shift+drag resize it; left button adds, right removes) with what it would paint shown under
// it, the magic wand (its selection shown) and Poisson-diffusion blending as tools, overlays of
// the selected layer's weight, its change map or Auto Start's choice map, and a large side
// preview of the selected filter applied everywhere.
#pragma once

#include <QColor>
#include <QImage>
#include <QList>
#include <QPair>
#include <QString>

#include <optional>

#include "glint/denoise/paint.h"
#include "model/task_runner.h"
#include "views/stage_view.h"

class QListWidget;
class QPushButton;
class QLabel;
class QSlider;
class QDoubleSpinBox;
class QCheckBox;
class QToolButton;

namespace glint::studio {

class PaintView : public StageView {
    Q_OBJECT
  public:
    PaintView(const StudioContext& context, QWidget* parent = nullptr);

    /// The layer strokes paint on (-1: none).
    int currentLayer() const;
    void setCurrentLayer(int index);
    denoise::Brush brush() const;
    void setBrushSize(double size);
    /// [ and ]: the brush shrinks or grows by a quarter.
    void growBrush(double factor);
    /// Diffuses the weights of every layer that has painted pixels.
    void diffuse();
    /// Shows or hides the selected layer's weight over the image (the O key).
    void toggleWeightOverlay();

  signals:
    /// The user asks to allow the program (a full path) the selected, unavailable layer runs.
    void allowProgramRequested(const QString& program);

  protected:
    void activate() override;
    void deactivate() override;

  private:
    void rebuildLayers();
    void layerSelected();
    void updateSidePreview();
    // Shows "Allow program…" when the selected layer waits for a program not allowed.
    void updateAllowButton();
    void updateOverlay();
    // Keeps at most one of the overlay boxes checked (the one just checked).
    void overlayChosen(QCheckBox* box, bool on);
    void showOverlay(const QImage& image, const QList<QPair<QColor, QString>>& legend);
    void strokeTo(const QPointF& at);
    void wand(const QPoint& pixel, bool subtract);

    TaskRunner m_tasks;
    QListWidget* m_layers;
    QPushButton* m_allowProgram;
    QString m_blockedProgram;  // the program the selected layer waits for
    QToolButton* m_brushTool;
    QToolButton* m_wandTool;
    QDoubleSpinBox* m_size;
    QSlider* m_softness;
    QDoubleSpinBox* m_wandTolerance;
    QCheckBox* m_showWeight;
    QCheckBox* m_changeMap;
    QCheckBox* m_choiceMap;
    QLabel* m_side;
    QLabel* m_state;
    std::optional<QPointF> m_lastDab;
    bool m_stroking = false;
};

}  // namespace glint::studio
