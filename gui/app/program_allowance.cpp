#include "app/program_allowance.h"

#include <QMessageBox>
#include <QPushButton>
#include <QTimer>

#include <algorithm>

#include "app/studio_settings.h"
#include "model/blocked_programs.h"
#include "model/session_adapter.h"

namespace glint::studio {

ProgramAllowance::ProgramAllowance(SessionAdapter* session, QWidget* window)
    : QObject(window), m_session(session), m_window(window) {
    // A session opened or restored, layers added: a queued look, once the session is in place.
    connect(m_session, &SessionAdapter::sessionReset, this, &ProgramAllowance::check,
            Qt::QueuedConnection);
    connect(m_session, &SessionAdapter::layersChanged, this, &ProgramAllowance::check,
            Qt::QueuedConnection);
}

void ProgramAllowance::check() {
    if (m_box || !m_session->hasSession()) return;
    for (const BlockedProgram& b : blockedPrograms(m_session->session()))
        if (!m_asked.contains(b.program)) {
            ask(b.program);
            return;
        }
}

void ProgramAllowance::ask(const QString& program) {
    if (m_box || !m_session->hasSession()) return;
    const std::vector<BlockedProgram> blocked = blockedPrograms(m_session->session());
    const auto it = std::find_if(blocked.begin(), blocked.end(),
                                 [&](const BlockedProgram& b) { return b.program == program; });
    if (it == blocked.end()) return;  // allowed meanwhile, or no layer names it any more
    if (!m_asked.contains(program)) m_asked << program;
    QStringList layers;
    for (std::size_t i : it->layers) layers << QString::number(i + 1);
    // Not modal: the studio goes on while the question waits.
    auto* box = new QMessageBox(
        QMessageBox::Warning, tr("Allow this program to run?"),
        tr("Layer %1 of this session is an external denoiser that runs the program\n\n%2\n\n"
           "which you have not allowed, so the layer is unavailable: it changes nothing. A "
           "session file never runs a program by itself.\n\nAllow it only if you trust it: it "
           "is kept in your settings (not in the session), and any session may then run it.")
            .arg(layers.join(QStringLiteral(", ")), program),
        QMessageBox::NoButton, m_window);
    box->setObjectName(QStringLiteral("allowProgram"));
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->setWindowModality(Qt::NonModal);
    box->setDetailedText(it->reason);
    QPushButton* allow = box->addButton(tr("Allow"), QMessageBox::AcceptRole);
    allow->setObjectName(QStringLiteral("allow"));
    QPushButton* later = box->addButton(tr("Not now"), QMessageBox::RejectRole);
    later->setObjectName(QStringLiteral("notNow"));
    box->setDefaultButton(later);
    connect(box, &QMessageBox::buttonClicked, this, [this, allow, program](QAbstractButton* b) {
        if (b != allow) return;
        if (!allowCommandForGood(program)) {
            emit failed(tr("Cannot allow the program"), tr("%1 is not a full path.").arg(program));
            return;
        }
        m_session->rerunLayers();
        emit allowed(program);
    });
    // The next program waiting, if any.
    connect(box, &QObject::destroyed, this,
            [this] { QTimer::singleShot(0, this, [this] { check(); }); });
    m_box = box;
    box->show();
}

}  // namespace glint::studio
