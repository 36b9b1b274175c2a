// Comparing with a reference: open a high-spp EXR or render one in the background; live SSIM,
// relMSE and PSNR of the raw render and of the result, for the image and for the region, side by
// side (did denoising help?), HDR-FLIP's mean with its map as a canvas overlay, per-channel
// min/mean/max of the region, error images, and the plot of the raw render's relMSE against time of
// the running render. A reference rendered for another scene, look or camera is said so beside the
// metrics, which are then marked stale.
#pragma once

#include <QImage>
#include <QTimer>

#include "model/task_runner.h"
#include "views/convergence_plot.h"
#include "views/stage_view.h"

class QCheckBox;
class QLabel;
class QSpinBox;
class QProgressBar;
class QTableWidget;
class QComboBox;

namespace glint::studio {

/// SSIM, relMSE, PSNR and HDR-FLIP of one image against the reference (FLIP: NaN when it
/// cannot be computed, e.g. for a reference mostly black).
struct Metrics {
    double ssim = 0.0, relMse = 0.0, psnr = 0.0, flip = 0.0;
};

/// What the compare view measured last.
struct Measurement {
    // The result (the composite).
    double ssimImage = 0.0, relMseImage = 0.0, psnrImage = 0.0;
    double ssimRegion = 0.0, relMseRegion = 0.0, psnrRegion = 0.0;
    /// HDR-FLIP (glint/image/flip.h) of the image; in the region, the mean of its map there.
    double flipImage = 0.0, flipRegion = 0.0;
    QImage flipMap;  ///< the result's FLIP map in magma (null without a reference)
    // The raw render the result was made from (the session's input): the same metric, the same
    // images as the convergence plot's last point over the whole image.
    Metrics rawImage, rawRegion;
    std::array<double, 3> min{}, mean{}, max{};  ///< of the result inside the region
    bool haveReference = false;
    bool haveRaw = false;
};

/// A figure of the metrics table (relMSE, PSNR, FLIP): three significant digits, plain from
/// 0.001 to 9999 ("0.00184", "36.7", "1234"), else in the exponent form without padding
/// ("7.51e-4", "1.23e5").
QString compactNumber(double v);

class CompareView : public StageView {
    Q_OBJECT
  public:
    CompareView(const StudioContext& context, QWidget* parent = nullptr);
    const Measurement& measurement() const { return m_measurement; }
    /// The warning that the reference was rendered for another scene, look or camera, or that
    /// what it was rendered for is not known (empty: none).
    QString lookWarning() const;
    /// The metrics compare with a reference of another scene, look or camera: the table shows
    /// "stale" instead of their values (kept in each cell's tooltip).
    bool metricsStale() const;
    /// The text of the metrics table's cell (row: SSIM, relMSE, PSNR, FLIP; column: raw, result,
    /// raw in the region, result in the region: the table shows the region's figures in rows
    /// under the image's) and its column's name ("Raw, image").
    QString cellText(int row, int column) const;
    QString columnTitle(int column) const;
    /// The line that answers "did denoising help?" (empty without a reference).
    QString verdict() const;
    /// What the convergence plot shows, as its drop-down says it.
    QString plotTitle() const;
    /// Shows the result's FLIP map over the canvas (when there is a reference) or hides it. The
    /// compare dock is always there, so the map stays until unticked (a stage's overlay, such
    /// as the paint stage's change map, replaces it until the next measurement).
    void setFlipMapShown(bool shown);

  signals:
    void measured();
    /// Asks the main window for a file to open as the reference.
    void openReferenceRequested();

  private:
    void schedule();
    void measure();
    void show();
    void updateLookWarning();
    void showFlipMap();

    TaskRunner m_tasks;
    QTimer m_debounce;
    QSpinBox* m_spp;
    QProgressBar* m_progress;
    QTableWidget* m_table;
    QLabel* m_stats;
    QLabel* m_verdict;
    QLabel* m_lookWarning;
    bool m_warnedLook = false;
    QComboBox* m_error;
    QCheckBox* m_flipMap;
    bool m_flipMapOnCanvas = false;
    QComboBox* m_axis;
    ConvergencePlot* m_plot;
    Measurement m_measurement;
};

}  // namespace glint::studio
