// Stage 1, features: albedo, normal and depth (histogram-equalised) and their variances on the
// canvas, and feature prefiltering for scenes whose features are noisy (motion blur, depth of
// field), tuned with controls generated from the prefilter's ParamSpecs.
#pragma once

#include "views/param_controls.h"
#include "views/stage_view.h"

class QCheckBox;
class QLabel;

namespace glint::studio {

class FeaturesView : public StageView {
    Q_OBJECT
  public:
    FeaturesView(const StudioContext& context, QWidget* parent = nullptr);
    /// Turns prefiltering on (with the controls' parameters) or off for the session.
    void setPrefilter(bool on);

  protected:
    void activate() override;
    void deactivate() override;

  private:
    void updateInfo();

    QCheckBox* m_prefilter;
    ParamControls* m_params;
    QLabel* m_info;
};

}  // namespace glint::studio
