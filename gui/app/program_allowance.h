// Allowing an external denoiser's program from the studio (docs/external-denoiser.md,
// "Security"): a session whose layer names a program the user has not allowed shows that layer
// as unavailable, and a question that blocks nothing names the program by its full path.
// "Allow" keeps it in the user's settings (never in the session file) and runs the layers again;
// "Not now" leaves the layer unavailable (the paint panel's "Allow program…" asks again).
#pragma once

#include <QMessageBox>
#include <QObject>
#include <QPointer>
#include <QStringList>

class QWidget;

namespace glint::studio {

class SessionAdapter;

class ProgramAllowance : public QObject {
    Q_OBJECT
  public:
    /// Watches `session`: each program its unavailable layers wait for is asked about once per
    /// window. The question is a child of `window`.
    ProgramAllowance(SessionAdapter* session, QWidget* window);

    /// Asks about `program` (a full path) now, even when it was asked about before.
    void ask(const QString& program);
    /// The question on screen (objectName "allowProgram"), or null.
    QMessageBox* question() const { return m_box; }

  signals:
    /// `program` was allowed and the layers are being run again.
    void allowed(const QString& program);
    void failed(const QString& title, const QString& message);

  private:
    void check();

    SessionAdapter* m_session;
    QWidget* m_window;
    QPointer<QMessageBox> m_box;
    QStringList m_asked;  // programs asked about in this window
};

}  // namespace glint::studio
