// A scene's first render is shown denoised, not raw: when a scene or an EXR is opened and its
// session starts with no layers, one layer of the cross-bilateral filter (its defaults, weight 1
// everywhere) is added, as the user could do by hand. It is an ordinary layer: one undo step,
// journalled, painted over or removed like any other. No widgets here.
#pragma once

#include <QObject>

#include <functional>

namespace glint::studio {

class Document;
class SessionAdapter;

class FirstDenoise : public QObject {
    Q_OBJECT
  public:
    /// The filter of the default layer.
    static constexpr const char* kFilter = "cross-bilateral";

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
