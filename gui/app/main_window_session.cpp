// The main window's session file: saving it with the region, the view, the look, the render
// settings and the reference, and restoring them when a session is opened (docs/studio.md,
// "Session files").
#include <QFileInfo>
#include <QSignalBlocker>
#include <QStatusBar>

#include "app/main_window.h"
#include "app/studio_settings.h"
#include "glint/image/error.h"
#include "model/journal_codec.h"
#include "model/progressive_render.h"
#include "model/reference_info.h"
#include "model/session_state.h"
#include "views/viewer.h"

namespace glint::studio {

bool MainWindow::isModified() const {
    return !m_session->undoStack()->isClean() || m_document->modified();
}

bool MainWindow::saveSession(const QString& path) {
    // Written on a worker; the state saved is the undo stack's present step.
    const int index = m_session->undoStack()->index();
    // A rendered reference's pixels go to the side folder; one read from a file stays there.
    std::map<std::string, FramePtr> frames;
    if (const std::optional<ReferenceInfo>& info = m_document->referenceInfo();
        info && info->source == ReferenceInfo::Source::Rendered && m_document->reference())
        frames[kReferenceFrame] = m_document->reference();
    try {
        m_session->save(path,
                        m_region->wholeImage()
                            ? std::nullopt
                            : std::optional<Rect>(m_region->bounds(m_session->session().width(),
                                                                   m_session->session().height())),
                        viewState(), frames, [this, path, index](const QString& error) {
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
    if (m_document->reference() && m_document->referenceInfo())
        writeReferenceState(*m_document->referenceInfo(), state);
    state["lasso"] = m_region->toString().toStdString();
    state["exposure"] = std::to_string(m_viewer->exposure());
    state["stage"] = std::to_string(stage());
    state["channel"] = channelKey(m_viewer->channel()).toStdString();
    // Render ▸ Keep Refining, a render option kept with the others.
    state["keepRefining"] = std::to_string(int(m_actions.keepRefining->isChecked()));
    return state;
}

void MainWindow::applyViewState(const std::map<std::string, std::string>& state) {
    auto get = [&](const char* key) {
        auto it = state.find(key);
        return it == state.end() ? QString() : QString::fromStdString(it->second);
    };
    m_region->fromString(get("lasso"));
    // The scene, opened without rendering, then given the saved look and settings before
    // anything renders: a look change renders and re-applies the layers.
    const QString scene = get("scene");
    if (!scene.isEmpty() && QFileInfo::exists(scene)) {
        m_restoring = true;
        auto once = std::make_shared<QMetaObject::Connection>();
        *once = connect(m_document, &Document::opened, this, [this, once, state] {
            disconnect(*once);
            const std::vector<render::LookItem> before = m_document->look();
            const std::string skipped = applyLook(state, *m_document);
            journalLookChanges(before);
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
            restoreReference(state);
        });
        m_document->open(scene, false);
    } else {
        restoreReference(state);
    }
    bool ok = false;
    const double exposure = get("exposure").toDouble(&ok);
    const QString refining = get("keepRefining");
    bool staged = false;
    const int stage = get("stage").toInt(&staged);
    // The channel by its key; a name no channel has is named (an older file has none: the
    // viewer's stays).
    const QString key = get("channel");
    const std::optional<Viewer::Channel> channel = channelFromKey(key);
    if (!key.isEmpty() && !channel)
        showError(tr("The session's viewer channel was not restored"),
                  tr("%1: \"channel\" is \"%2\", which is no channel of the viewer (expected "
                     "%3 or another name the studio writes)")
                      .arg(m_sessionPath, key, channelKey(Viewer::Channel::Result)));
    setView(ok ? std::optional(exposure) : std::nullopt,
            refining.isEmpty() ? std::nullopt : std::optional(refining == QLatin1String("1")),
            staged ? std::optional(stage) : std::nullopt, channel);
}

void MainWindow::journalLookChanges(const std::vector<render::LookItem>& before) {
    // The look a session file gave its scene, for the autosave (not an undo step). Setting a
    // value changes no item or property, only values: the two lists align.
    const std::vector<render::LookItem>& after = m_document->look();
    for (std::size_t i = 0; i < after.size() && i < before.size(); ++i)
        for (std::size_t j = 0; j < after[i].properties.size() && j < before[i].properties.size();
             ++j) {
            const render::LookProperty& p = after[i].properties[j];
            if (p.value != before[i].properties[j].value)
                m_session->record(
                    {journal_codec::encodeSetLook(after[i].name, p.name, p.value), {}, nullptr});
        }
}

void MainWindow::setKeepRefiningQuietly(bool on) {
    // The toggle alone: the next render refines (restoring renders nothing).
    const QSignalBlocker quiet(m_actions.keepRefining);
    m_actions.keepRefining->setChecked(on);
    m_progressive->setEnabled(on);
}

void MainWindow::setView(std::optional<double> exposure, std::optional<bool> keepRefining,
                         std::optional<int> stage, std::optional<Viewer::Channel> channel) {
    // Each part would journal the view on its own (the exposure's signal, the stage): one line,
    // once all are set.
    m_viewJournalHeld = true;
    if (keepRefining) setKeepRefiningQuietly(*keepRefining);
    if (exposure) m_viewer->setExposure(*exposure);
    if (stage) setStage(std::clamp(*stage, 0, journal_codec::kStages - 1));
    if (channel) m_viewer->setChannel(*channel);
    m_viewJournalHeld = false;
    journalView();
}

void MainWindow::journalView() {
    if (m_viewJournalHeld) return;
    const journal_codec::View view{.exposure = m_viewer->exposure(),
                                   .keepRefining = m_actions.keepRefining->isChecked(),
                                   .stage = stage(),
                                   .channel = channelKey(m_viewer->channel()).toStdString()};
    m_session->record({journal_codec::encodeView(view), {}, nullptr});
}

void MainWindow::restoreReference(const std::map<std::string, std::string>& state) {
    const std::optional<ReferenceInfo> info = readReferenceState(state, m_document->look());
    if (!info || !m_session->hasSession()) return;
    FramePtr frame;
    const auto& frames = m_session->session().sideFrames;
    if (const auto it = frames.find(kReferenceFrame);
        info->source == ReferenceInfo::Source::Rendered && it != frames.end())
        frame = it->second;
    // What the session file holds: it does not make the window unsaved.
    m_document->restoreReference(*info, frame, true);
}

}  // namespace glint::studio
