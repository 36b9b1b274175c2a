// Stage 3 by tuning: a filter menu (by display name) and sliders generated from the filter's
// ParamSpecs, a live preview of the region (computed in the background, superseded by the next
// change), and the parameters remembered per filter. It opens on the current result's filter.
#pragma once

#include <QTimer>

#include <map>
#include <string>

#include "model/task_runner.h"
#include "views/param_controls.h"
#include "views/stage_view.h"

class QComboBox;
class QLabel;
class QCheckBox;

namespace glint::studio {

class TuneView : public StageView {
    Q_OBJECT
  public:
    TuneView(const StudioContext& context, QWidget* parent = nullptr);

    std::string filter() const;
    void setFilter(const std::string& name);
    denoise::ParamValues values() const { return m_controls->values(); }
    /// Sets parameter values of the current filter (as the sliders would).
    void setValues(const denoise::ParamValues& values);
    /// Adds the filter as a layer (filled over the region when `fillRegion`).
    void choose(bool fillRegion);
    /// True once the preview of the current values is on the canvas.
    bool previewReady() const { return m_previewReady; }

  signals:
    void previewShown();

  protected:
    void activate() override;
    void deactivate() override;

  private:
    void filterChanged();
    void schedulePreview();
    void computePreview();
    /// Until the user picks a filter or moves a control, the panel opens on the top layer's
    /// filter and parameters (what the result shows), else on the first image's filter.
    void startFromTheResult();

    TaskRunner m_tasks;
    QTimer m_debounce;
    QComboBox* m_filter;
    QLabel* m_description;
    ParamControls* m_controls;
    QCheckBox* m_preview;
    QLabel* m_state;
    std::map<std::string, denoise::ParamValues> m_memory;
    bool m_previewReady = false;
    bool m_userChose = false;  // a filter or a value was chosen (by the user or setFilter)
};

}  // namespace glint::studio
