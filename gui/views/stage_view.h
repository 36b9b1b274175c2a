// What every workflow stage (features, region, tune, navigate, paint) shares: the model it
// edits, the viewer it draws on, and being told when it becomes the active stage (it then owns
// the canvas tool and overlays).
#pragma once

#include <QWidget>

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
    StageView(const StudioContext& context, QWidget* parent = nullptr)
        : QWidget(parent), m_context(context) {}
    /// Makes this the active stage (it owns the canvas tool and overlays) or not.
    void setActive(bool on) {
        m_active = on;
        if (on)
            activate();
        else
            deactivate();
    }
    bool active() const { return m_active; }

  signals:
    /// Shown in the status bar.
    void status(const QString& message);
    /// A filter was chosen and is being added as a layer: the paint stage comes next.
    void layerChosen();
    void failed(const QString& title, const QString& message);

  protected:
    /// The stage became active: set the canvas tool and overlays.
    virtual void activate() {}
    /// Another stage became active: remove what this one put on the canvas.
    virtual void deactivate() {}

    StudioContext m_context;
    bool m_active = false;
};

}  // namespace glint::studio
