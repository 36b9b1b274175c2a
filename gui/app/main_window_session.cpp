// The main window's session file: saving it with the region, the view, the look and the render
// settings, and restoring them when a session is opened (docs/studio.md, "Session files").
#include <QFileInfo>
#include <QStatusBar>

#include "app/main_window.h"
#include "app/studio_settings.h"
#include "glint/image/error.h"
#include "model/session_state.h"
#include "views/viewer.h"

namespace glint::studio {

bool MainWindow::isModified() const {
    return !m_session->undoStack()->isClean() || m_document->modified();
}

bool MainWindow::saveSession(const QString& path) {
    // Written on a worker; the state saved is the undo stack's present step.
    const int index = m_session->undoStack()->index();
    try {
        m_session->save(path,
                        m_region->wholeImage()
                            ? std::nullopt
                            : std::optional<Rect>(m_region->bounds(m_session->session().width(),
                                                                   m_session->session().height())),
                        viewState(), [this, path, index](const QString& error) {
                            std::function<void()> then = std::exchange(m_afterSave, {});
                            if (!error.isEmpty()) {
                                showError(tr("Cannot save the session"), error);
                                return;
                            }
                            m_sessionPath = path;
                            if (m_session->undoStack()->index() == index)
                                m_session->undoStack()->setClean();
                            m_document->markSaved();
                            addRecentFile(path);
                            rebuildRecent();
                            statusBar()->showMessage(tr("Saved %1").arg(path), 4000);
                            updateTitle();
                            if (then) then();
                        });
        return true;
    } catch (const Error& e) {
        m_afterSave = {};
        showError(tr("Cannot save the session"), QString::fromStdString(e.what()));
        return false;
    }
}

std::map<std::string, std::string> MainWindow::viewState() const {
    std::map<std::string, std::string> state;
    if (m_document->kind() == Document::Kind::Scene) {
        state["scene"] = QFileInfo(m_document->path()).absoluteFilePath().toStdString();
        // The look as edited and the render settings: reopening renders what was saved.
        writeDocumentState(m_document->look(), m_document->settings(), state);
    }
    state["lasso"] = m_region->toString().toStdString();
    state["exposure"] = std::to_string(m_viewer->exposure());
    state["stage"] = std::to_string(stage());
    return state;
}

void MainWindow::applyViewState(const std::map<std::string, std::string>& state) {
    auto get = [&](const char* key) {
        auto it = state.find(key);
        return it == state.end() ? QString() : QString::fromStdString(it->second);
    };
    m_region->fromString(get("lasso"));
    bool ok = false;
    const double exposure = get("exposure").toDouble(&ok);
    if (ok) m_viewer->setExposure(exposure);
    // The scene, opened without rendering, then given the saved look and settings before
    // anything renders: a look change renders and re-applies the layers.
    const QString scene = get("scene");
    if (!scene.isEmpty() && QFileInfo::exists(scene)) {
        m_restoring = true;
        auto once = std::make_shared<QMetaObject::Connection>();
        *once = connect(m_document, &Document::opened, this, [this, once, state] {
            disconnect(*once);
            const std::string skipped = applyLook(state, *m_document);
            try {
                m_document->setSettings(readSettings(state, m_document->settings(),
                                                     m_sessionPath.toStdString(), "/view/"));
            } catch (const Error& e) {
                showError(tr("The session's render settings were not restored"),
                          QString::fromStdString(e.what()));
            }
            if (!skipped.empty())
                showError(tr("Part of the session's look was not restored"),
                          tr("The scene has no such property, or refuses the value: %1")
                              .arg(QString::fromStdString(skipped)));
            m_restoring = false;
            m_document->setFinishedFrame(m_session->input());
        });
        m_document->open(scene, false);
    }
    const int s = get("stage").toInt(&ok);
    if (ok) setStage(std::clamp(s, 0, 3));
}

}  // namespace glint::studio
