// Stage 2, the region of interest: a free-form lasso (or a rectangle) drawn on the image, or the
// whole image (the default). The tune and navigate stages preview and build their bank there.
#pragma once

#include "views/stage_view.h"

class QLabel;
class QToolButton;

namespace glint::studio {

class RegionView : public StageView {
    Q_OBJECT
  public:
    RegionView(const StudioContext& context, QWidget* parent = nullptr);

  protected:
    void activate() override;
    void deactivate() override;

  private:
    void updateLabel();

    QToolButton* m_lasso;
    QToolButton* m_rectangle;
    QLabel* m_label;
};

}  // namespace glint::studio
