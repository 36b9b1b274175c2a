// A long render under a painted session shows its passes denoised as they arrive, not only once
// it has finished: a pass with at least as many samples per pixel as the render the session
// holds (so never noisier than the denoised image on screen) becomes the session's input, its
// layers re-applied in the background. One re-application at a time: of the passes that arrive
// while one runs, the latest is taken when it ends (the others are skipped). Previews are not
// journalled (the finished render is). No widgets here.
#pragma once

#include <QObject>

#include <functional>

namespace glint::studio {

class Document;
class SessionAdapter;

class ProgressiveDenoise : public QObject {
    Q_OBJECT
  public:
    /// Watches `document`'s passes; `allowed()` is asked first (false while a journal is
    /// restored).
    ProgressiveDenoise(Document* document, SessionAdapter* session, std::function<bool()> allowed,
                       QObject* parent = nullptr);

    /// Passes shown denoised so far (tests).
    int previews() const { return m_previews; }

  private:
    void onPass();

    Document* m_document;
    SessionAdapter* m_session;
    std::function<bool()> m_allowed;
    int m_previews = 0;
};

}  // namespace glint::studio
