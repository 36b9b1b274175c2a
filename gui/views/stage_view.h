// What every workflow stage (features, region, tune, navigate, paint) shares: the model it
// edits, the viewer it draws on, and being told when it becomes the active stage (it then owns
// the canvas tool and overlays). A stage's tool buttons form one exclusive group that follows
// the canvas: the canvas's tool is the one source of truth, buttons and shortcuts both set it.
#pragma once

#include <QWidget>

class QAbstractButton;
class QButtonGroup;

#include "model/document.h"
#include "model/region.h"
#include "model/session_adapter.h"
#include "views/viewer.h"

namespace glint::studio {

/// The model objects and the viewer the panels share (owned by the main window).
struct StudioContext {
    Document* document = nullptr;
    SessionAdapter* session = nullptr;
    RegionOfInterest* region = nullptr;
    Viewer* viewer = nullptr;
};

/// Adds a layer of `filter` to the session; with `fillRegion` its weight is 1 inside the region.
inline void addChosenLayer(const StudioContext& context, const std::string& filter,
                           const denoise::ParamValues& params, bool fillRegion) {
    FramePtr input = context.session->input();
    if (!input) return;
    std::optional<Image> mask;
    if (fillRegion) mask = context.region->mask(input->width(), input->height());
    context.session->addLayer(filter, params, std::move(mask));
}

class StageView : public QWidget {
    Q_OBJECT
  public:
    StageView(const StudioContext& context, QWidget* parent = nullptr);
    /// Makes this the active stage (it owns the canvas tool and overlays) or not.
    void setActive(bool on) {
        m_active = on;
        if (on)
            activate();
        else
            deactivate();
    }
    bool active() const { return m_active; }
    /// The canvas tool of this stage: its checked tool button (Pan without tool buttons).
    ImageCanvas::Tool tool() const;
    /// Checks the button of `tool` (a shortcut's way in); the canvas follows when active.
    void selectTool(ImageCanvas::Tool tool);
    /// Puts this stage's tool on the canvas.
    void applyTool();

  signals:
    /// Shown in the status bar.
    void status(const QString& message);
    /// A filter was chosen and is being added as a layer: the paint stage comes next.
    void layerChosen();
    void failed(const QString& title, const QString& message);

  protected:
    /// The stage became active: set the canvas tool and overlays.
    virtual void activate() { applyTool(); }
    /// Another stage became active: remove what this one put on the canvas.
    virtual void deactivate() {}
    /// Adds `button` to the stage's exclusive tool group as `tool`.
    void addToolButton(QAbstractButton* button, ImageCanvas::Tool tool);

    StudioContext m_context;
    bool m_active = false;

  private:
    QButtonGroup* m_tools = nullptr;
};

}  // namespace glint::studio
