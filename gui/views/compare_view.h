// Comparing with a reference: open a high-spp EXR or render one in the background; live SSIM,
// relMSE and PSNR of the result for the image and the region, per-channel min/mean/max of the
// region, error images, and the relMSE-versus-time plot of the running render.
#pragma once

#include <QTimer>

#include "model/task_runner.h"
#include "views/convergence_plot.h"
#include "views/stage_view.h"

class QLabel;
class QSpinBox;
class QProgressBar;
class QTableWidget;
class QComboBox;

namespace glint::studio {

/// What the compare view measured last.
struct Measurement {
    double ssimImage = 0.0, relMseImage = 0.0, psnrImage = 0.0;
    double ssimRegion = 0.0, relMseRegion = 0.0, psnrRegion = 0.0;
    std::array<double, 3> min{}, mean{}, max{};  ///< of the result inside the region
    bool haveReference = false;
};

class CompareView : public StageView {
    Q_OBJECT
  public:
    CompareView(const StudioContext& context, QWidget* parent = nullptr);
    const Measurement& measurement() const { return m_measurement; }
    /// The warning that the reference's look is not the current one (empty: none).
    QString lookWarning() const;

  signals:
    void measured();
    /// Asks the main window for a file to open as the reference.
    void openReferenceRequested();

  private:
    void schedule();
    void measure();
    void show();
    void updateLookWarning();

    TaskRunner m_tasks;
    QTimer m_debounce;
    QSpinBox* m_spp;
    QProgressBar* m_progress;
    QTableWidget* m_table;
    QLabel* m_stats;
    QLabel* m_lookWarning;
    bool m_warnedLook = false;
    QComboBox* m_error;
    ConvergencePlot* m_plot;
    Measurement m_measurement;
};

}  // namespace glint::studio
