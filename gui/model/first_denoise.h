// A scene's first render is shown denoised, not raw: when a scene or an EXR is opened and its
// session starts with no layers, one layer (its filter's defaults, weight 1 everywhere) is added,
// as the user could do by hand: the learned filter (unet) when its weights are present and the
// render has albedo and normal, else the cross-bilateral filter when the render has its guides
// (docs/studio.md says why: unet is better at the studio's spp on every scene measured). It is an
// ordinary layer: one undo step, journalled, painted over or removed like any other. No widgets
// here.
#pragma once

#include <QObject>

#include <functional>
#include <string>

#include "glint/image/frame_buffers.h"

namespace glint::studio {

class Document;
class SessionAdapter;

class FirstDenoise : public QObject {
    Q_OBJECT
  public:
    /// The filter of the default layer without the learned one.
    static constexpr const char* kClassicalFilter = "cross-bilateral";
    /// The filter of the default layer on `frame`: the learned filter (model/learned_member.h)
    /// when it runs here and the frame has albedo and normal, else kClassicalFilter when the
    /// frame has its guides (albedo, normal, depth), else "" (the render stays raw).
    static std::string filterFor(const FrameBuffers& frame);

    /// Watches `document` and `session`; `allowed()` is asked before a layer is added (false
    /// while a journal is restored, or when the user turned the default off).
    FirstDenoise(Document* document, SessionAdapter* session, std::function<bool()> allowed,
                 QObject* parent = nullptr);

  private:
    void onSessionReset();

    Document* m_document;
    SessionAdapter* m_session;
    std::function<bool()> m_allowed;
    bool m_armed = false;  // a file was opened and its first session has not started yet
};

}  // namespace glint::studio
