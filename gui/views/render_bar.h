// The render bar: spp, seed, integrator, MIS and half buffers; Render, Pause/Resume, Cancel; the
// render-region tool; a progress bar with passes, samples and time.
#pragma once

#include <QWidget>

#include "model/document.h"
#include "model/render_eta.h"
#include "views/image_canvas.h"

class QSpinBox;
class QCheckBox;
class QComboBox;
class QPushButton;
class QProgressBar;
class QLabel;
class QToolButton;

namespace glint::studio {

class RenderBar : public QWidget {
    Q_OBJECT
  public:
    RenderBar(Document* document, ImageCanvas* canvas, QWidget* parent = nullptr);

    /// Reads the settings from the controls into the document (throws glint::Error).
    void applySettings();
    QPushButton* renderButton() { return m_render; }
    QPushButton* cancelButton() { return m_cancel; }
    QPushButton* pauseButton() { return m_pause; }
    QToolButton* regionButton() { return m_regionTool; }
    QCheckBox* halvesBox() { return m_halves; }
    QSpinBox* sppBox() { return m_spp; }
    /// The running render's time left ("~12 s left"), empty until there is an estimate.
    QString remaining() const;
    /// Leaves the render-region tool (after its one rectangle, or when the stage changes).
    void disarmRegionTool();

  signals:
    /// The user asked for the render-region tool (true) or left it.
    void regionToolToggled(bool on);
    void failed(const QString& title, const QString& message);

  private:
    void syncFromDocument();
    /// Shows the document's settings in the controls (a restored session's, for one).
    void showSettings();
    /// A control changed: the document takes the settings at once (they are saved with it).
    void controlChanged();
    void updateState();

    Document* m_document;
    ImageCanvas* m_canvas;
    QSpinBox* m_spp;
    QSpinBox* m_seed;
    QComboBox* m_integrator;
    QComboBox* m_mis;
    QCheckBox* m_halves;
    QPushButton* m_render;
    QPushButton* m_pause;
    QPushButton* m_cancel;
    QToolButton* m_regionTool;
    QToolButton* m_clearRegion;
    QProgressBar* m_progress;
    QLabel* m_info;
    QLabel* m_remaining;
    bool m_rendered = false;  // a render ran since the last final frame
    RemainingTime m_eta;
};

}  // namespace glint::studio
