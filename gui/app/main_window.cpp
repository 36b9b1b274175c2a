#include "app/main_window.h"

#include <QApplication>
#include <QCloseEvent>
#include <QDir>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QStatusBar>
#include <QTabWidget>
#include <QToolBar>

#include "app/canvas_keys.h"
#include "app/file_naming.h"
#include "app/panel_layout.h"
#include "app/program_allowance.h"
#include "app/studio_settings.h"
#include "app/wheel_guard.h"
#include "glint/image/error.h"
#include "model/first_denoise.h"
#include "model/journal_codec.h"
#include "model/openable_files.h"
#include "model/progressive_denoise.h"
#include "model/progressive_render.h"
#include "views/compare_view.h"
#include "views/elided_label.h"
#include "views/features_view.h"
#include "views/help_overlay.h"
#include "views/look_panel.h"
#include "views/navigate_view.h"
#include "views/paint_view.h"
#include "views/region_view.h"
#include "views/render_bar.h"
#include "views/tune_view.h"
#include "views/viewer.h"

namespace glint::studio {

namespace {

bool isSessionPath(const QString& path) {
    return path.endsWith(QStringLiteral(".glint-session.json"), Qt::CaseInsensitive);
}

}  // namespace

MainWindow::MainWindow(const StudioOptions& options, QWidget* parent)
    : QMainWindow(parent), m_options(options) {
    setObjectName(QStringLiteral("GlintStudio"));
    setAcceptDrops(true);
    m_document = new Document(this);
    m_session = new SessionAdapter(this);
    m_region = new RegionOfInterest(this);
    new FirstDenoise(
        m_document, m_session, [this] { return m_options.denoiseFirstImage && !m_restoring; },
        this);
    new ProgressiveDenoise(
        m_document, m_session, [this] { return !m_restoring; }, this);
    m_progressive = new ProgressiveRender(this);
    m_document->setProgressive(m_progressive);
    m_allowance = new ProgramAllowance(m_session, this);
    m_autosave = std::make_unique<Autosave>(
        options.autosaveBase.isEmpty() ? Autosave::defaultBase() : options.autosaveBase, m_session);
    m_autosave->watch(m_document);
    m_actions = createActions(this);

    m_viewer = new Viewer(m_document, m_session, this);
    setCentralWidget(m_viewer);
    const StudioContext context{m_document, m_session, m_region, m_viewer};
    m_features = new FeaturesView(context);
    m_regionView = new RegionView(context);
    m_tune = new TuneView(context);
    m_navigate = new NavigateView(context);
    m_paint = new PaintView(context);
    m_compare = new CompareView(context);
    m_look = new LookPanel(m_document, m_session);
    m_renderBar = new RenderBar(m_document, m_viewer->canvas());

    // Each panel scrolls in its dock: no stage makes the window taller than a 768-px screen.
    m_filterTabs = new QTabWidget;
    m_filterTabs->addTab(new VerticalScrollArea(m_tune), tr("Tune"));
    m_filterTabs->addTab(new VerticalScrollArea(m_navigate), tr("Navigate"));
    m_stages = new QTabWidget;
    m_stages->addTab(new VerticalScrollArea(m_features), tr("1 Features"));
    m_stages->addTab(new VerticalScrollArea(m_regionView), tr("2 Region"));
    m_stages->addTab(m_filterTabs, tr("3 Filter"));
    m_stages->addTab(new VerticalScrollArea(m_paint), tr("4 Paint"));

    auto* bar = new QToolBar(tr("Render bar"), this);
    bar->setObjectName(QStringLiteral("renderBar"));
    bar->setMovable(false);
    bar->addWidget(m_renderBar);
    addToolBar(Qt::TopToolBarArea, bar);
    m_look->setMinimumWidth(kPanelMinWidth - 20);
    // The workflow has the right column to itself (Navigate's previews need its height); the
    // comparison sits under the look on the left, which keeps the larger share.
    QDockWidget* look = makeDock(this, tr("Look"), QStringLiteral("look"), m_look);
    QDockWidget* compare =
        makeDock(this, tr("Compare"), QStringLiteral("compare"), new VerticalScrollArea(m_compare));
    addDockWidget(Qt::LeftDockWidgetArea, look);
    addDockWidget(Qt::LeftDockWidgetArea, compare);
    QDockWidget* workflow = makeDock(this, tr("Workflow"), QStringLiteral("stages"), m_stages);
    addDockWidget(Qt::RightDockWidgetArea, workflow);

    m_readout = new ElidedLabel(this);
    m_readout->setTextInteractionFlags(Qt::TextSelectableByMouse);
    m_busy = new QLabel(this);
    m_busyProgress = new QProgressBar(this);
    m_busyProgress->setRange(0, 1000);
    m_busyProgress->setMaximumWidth(120);
    m_busyProgress->setTextVisible(false);
    m_busyProgress->hide();
    statusBar()->addWidget(m_readout, 1);
    statusBar()->addPermanentWidget(m_busy);
    statusBar()->addPermanentWidget(m_busyProgress);

    m_help = new HelpOverlay(this);
    m_help->setActions(m_actions.all());
    buildMenus();
    new CanvasKeys(this, m_viewer->canvas(), m_actions.all());
    connectModel();
    connectTev();
    new WheelGuard(this);
    // The preferred size, or what fits the screen; a restored geometry inside it stays.
    placeOnScreen(*this, QSize(1400, 860));
    // Without a saved layout the panels start as wide as they would like (the viewer gives).
    if (!restoreWindowState(*this))
        resizeDocks({look, workflow}, {look->sizeHint().width(), workflow->sizeHint().width()},
                    Qt::Horizontal);
    placeOnScreen(*this, QSize(1400, 860), true);
    keepPanelsWide(this, {workflow, look});
    updateTitle();
    stageChanged();
    m_viewer->canvas()->setFocus();
}

MainWindow::~MainWindow() = default;

void MainWindow::buildMenus() {
    const StudioActions& a = m_actions;
    QMenu* file = menuBar()->addMenu(tr("&File"));
    file->addAction(a.open);
    m_recentMenu = file->addMenu(tr("Open &Recent"));
    file->addAction(a.openReference);
    file->addSeparator();
    file->addAction(a.saveSession);
    file->addAction(a.saveSessionAs);
    file->addAction(a.saveScene);
    file->addAction(a.exportExr);
    file->addAction(a.exportPng);
    file->addSeparator();
    file->addAction(a.newSession);
    file->addAction(a.recover);
    file->addSeparator();
    file->addAction(a.quit);
    QMenu* edit = menuBar()->addMenu(tr("&Edit"));
    edit->addAction(a.undo);
    edit->addAction(a.redo);
    QMenu* render = menuBar()->addMenu(tr("&Render"));
    render->addAction(a.render);
    render->addAction(a.cancelRender);
    render->addAction(a.keepRefining);
    QMenu* view = menuBar()->addMenu(tr("&View"));
    for (QAction* x : {a.fit, a.oneToOne, a.flip, a.exposureUp, a.exposureDown}) view->addAction(x);
    // Each panel (and the render bar) shown or hidden: a closed dock comes back from here.
    view->addSeparator();
    for (QDockWidget* dock : findChildren<QDockWidget*>(Qt::FindDirectChildrenOnly))
        view->addAction(dock->toggleViewAction());
    for (QToolBar* toolBar : findChildren<QToolBar*>(Qt::FindDirectChildrenOnly))
        view->addAction(toolBar->toggleViewAction());
    QMenu* work = menuBar()->addMenu(tr("&Workflow"));
    for (QAction* s : a.stages) work->addAction(s);
    work->addSeparator();
    for (QAction* x : {a.lasso, a.wholeImage, a.same, a.back, a.brush, a.wand, a.brushSmaller,
                       a.brushLarger, a.diffuse, a.showWeight, a.autoStart})
        work->addAction(x);
    QMenu* help = menuBar()->addMenu(tr("&Help"));
    help->addAction(a.help);
    rebuildRecent();

    connect(a.open, &QAction::triggered, this, [this] {
        const QString path = askPath(tr("Open"), openDialogFilter(), false);
        if (!path.isEmpty()) openFile(path);
    });
    connect(a.openReference, &QAction::triggered, this, [this] {
        const QString path = askPath(tr("Open a reference"), tr("OpenEXR (*.exr)"), false);
        if (!path.isEmpty()) m_document->openReference(path);
    });
    connect(a.saveSession, &QAction::triggered, this, [this] {
        if (m_sessionPath.isEmpty())
            m_actions.saveSessionAs->trigger();
        else
            saveSession(m_sessionPath);
    });
    connect(a.saveSessionAs, &QAction::triggered, this, [this] {
        const QString path =
            askPath(tr("Save the session"), tr("Glint sessions (*.glint-session.json)"), true);
        if (path.isEmpty()) {
            m_afterSave = {};  // nothing is saved: the action maybeSave() held is dropped
            return;
        }
        saveSession(path);
    });
    connect(a.saveScene, &QAction::triggered, this, [this] {
        if (m_document->kind() != Document::Kind::Scene) {
            showError(tr("Nothing to save"),
                      tr("Only a scene opened from scene.json can be saved as JSON."));
            return;
        }
        const QString path =
            askPath(tr("Save the scene"), tr("Scenes (*.json)"), true, QStringLiteral("-edited"));
        if (!path.isEmpty()) m_document->saveScene(path);
    });
    connect(a.exportExr, &QAction::triggered, this, [this] { exportResult(true); });
    connect(a.exportPng, &QAction::triggered, this, [this] { exportResult(false); });
    connect(a.newSession, &QAction::triggered, this, [this] {
        if (!maybeSave([this] { m_actions.newSession->trigger(); })) return;
        m_session->clear();
        if (m_document->finishedFrame()) m_session->setInput(m_document->finishedFrame());
    });
    connect(a.recover, &QAction::triggered, this, [this] {
        // The newest crashed studio's autosave, else one kept aside, chosen.
        const QStringList crashed = Autosave::crashed(autosaveBase());
        const QString folder = !crashed.isEmpty()
                                   ? crashed.first()
                                   : QFileDialog::getExistingDirectory(
                                         this, tr("Recover an autosave"), autosaveBase());
        if (!folder.isEmpty()) restoreFrom(folder);
    });
    connect(a.quit, &QAction::triggered, this, &QWidget::close);
    connect(a.undo, &QAction::triggered, m_session->undoStack(), &QUndoStack::undo);
    connect(a.redo, &QAction::triggered, m_session->undoStack(), &QUndoStack::redo);
    connect(m_session->undoStack(), &QUndoStack::canUndoChanged, a.undo, &QAction::setEnabled);
    connect(m_session->undoStack(), &QUndoStack::canRedoChanged, a.redo, &QAction::setEnabled);
    connect(m_session->undoStack(), &QUndoStack::undoTextChanged, this, [this](const QString& t) {
        m_actions.undo->setText(t.isEmpty() ? tr("&Undo") : tr("&Undo %1").arg(t));
    });
    connect(m_session->undoStack(), &QUndoStack::redoTextChanged, this, [this](const QString& t) {
        m_actions.redo->setText(t.isEmpty() ? tr("&Redo") : tr("&Redo %1").arg(t));
    });
    connect(m_session->undoStack(), &QUndoStack::cleanChanged, this, &MainWindow::updateTitle);
    a.undo->setEnabled(false);
    a.redo->setEnabled(false);
    connect(m_session, &SessionAdapter::lockedChanged, this, [this](bool locked) {
        // While diffusion reads the session nothing may change it.
        m_actions.undo->setEnabled(!locked && m_session->undoStack()->canUndo());
        m_actions.redo->setEnabled(!locked && m_session->undoStack()->canRedo());
    });
    connect(a.render, &QAction::triggered, m_renderBar->renderButton(), &QPushButton::click);
    connect(a.cancelRender, &QAction::triggered, m_document, &Document::cancelRender);
    connect(a.keepRefining, &QAction::toggled, this, [this](bool on) {
        // On: the scene refines from a new render; off: a refinement under way stops there.
        m_progressive->setEnabled(on);
        journalView();
        if (on && m_document->kind() == Document::Kind::Scene && !m_document->rendering())
            m_document->render();
        if (!on && m_document->refining()) m_document->cancelRender();
    });
    connect(a.fit, &QAction::triggered, m_viewer->canvas(), &ImageCanvas::fit);
    connect(a.oneToOne, &QAction::triggered, m_viewer->canvas(), &ImageCanvas::oneToOne);
    connect(a.flip, &QAction::triggered, m_viewer, &Viewer::toggleFlip);
    connect(a.wipe, &QAction::triggered, m_viewer, &Viewer::toggleWipe);
    connect(a.exposureUp, &QAction::triggered, this,
            [this] { m_viewer->setExposure(m_viewer->exposure() + 0.5); });
    connect(a.exposureDown, &QAction::triggered, this,
            [this] { m_viewer->setExposure(m_viewer->exposure() - 0.5); });
    for (int i = 0; i < 4; ++i)
        connect(a.stages[std::size_t(i)], &QAction::triggered, this, [this, i] { setStage(i); });
    connect(a.lasso, &QAction::triggered, this, [this] {
        setStage(1);
        m_regionView->selectTool(ImageCanvas::Tool::Lasso);
    });
    connect(a.wholeImage, &QAction::triggered, m_region, &RegionOfInterest::clear);
    connect(a.brushSmaller, &QAction::triggered, this, [this] { m_paint->growBrush(0.8); });
    connect(a.brushLarger, &QAction::triggered, this, [this] { m_paint->growBrush(1.25); });
    connect(a.brush, &QAction::triggered, this, [this] {
        setStage(3);
        m_paint->selectTool(ImageCanvas::Tool::Brush);
    });
    connect(a.wand, &QAction::triggered, this, [this] {
        setStage(3);
        m_paint->selectTool(ImageCanvas::Tool::Wand);
    });
    connect(a.diffuse, &QAction::triggered, m_paint, &PaintView::diffuse);
    connect(a.showWeight, &QAction::triggered, this, [this] {
        setStage(3);
        m_paint->toggleWeightOverlay();
    });
    connect(a.autoStart, &QAction::triggered, this, [this] {
        setStage(3);
        m_session->autoStart();
    });
    connect(a.same, &QAction::triggered, this, [this] {
        if (activeStage() == m_navigate) m_navigate->same();
    });
    connect(a.back, &QAction::triggered, this, [this] {
        if (activeStage() == m_navigate) m_navigate->back();
    });
    connect(a.help, &QAction::triggered, m_help, &HelpOverlay::toggle);
    for (QAction* x : m_actions.all()) addAction(x);
}

void MainWindow::connectModel() {
    connect(m_document, &Document::opened, this, [this] {
        addRecentFile(m_document->path());
        rebuildRecent();
        m_autosave->recordOpen(*m_document);
        if (!m_restoring) m_region->clear();  // a restored session brings its own region
        updateTitle();
        if (!m_document->openNote().isEmpty()) showStatus(m_document->openNote());
    });
    connect(m_document, &Document::frameChanged, this, [this](bool final) {
        // A finished render goes to the session: its layers are re-applied to it.
        if (final && !m_restoring && m_document->finishedFrame())
            m_session->setInput(m_document->finishedFrame());
    });
    connect(m_document, &Document::modifiedChanged, this, &MainWindow::updateTitle);
    connect(m_document, &Document::failed, this, &MainWindow::showError);
    connect(m_session, &SessionAdapter::failed, this, &MainWindow::showError);
    connect(m_session, &SessionAdapter::status, this,
            [this](const QString& m) { statusBar()->showMessage(m, 8000); });
    connect(m_renderBar, &RenderBar::failed, this, &MainWindow::showError);
    connect(m_look, &LookPanel::failed, this, &MainWindow::showError);
    connect(m_renderBar, &RenderBar::regionToolToggled, this, [this](bool on) {
        // Armed: one rectangle to render. Disarmed: the stage's own tool again.
        if (on)
            m_viewer->canvas()->setTool(ImageCanvas::Tool::RenderRegion);
        else if (m_activeStage)
            m_activeStage->applyTool();
        else
            m_viewer->canvas()->setTool(ImageCanvas::Tool::Pan);
    });
    for (StageView* s : std::initializer_list<StageView*>{m_features, m_regionView, m_tune,
                                                          m_navigate, m_paint, m_compare}) {
        connect(s, &StageView::failed, this, &MainWindow::showError);
        connect(s, &StageView::status, this,
                [this](const QString& m) { statusBar()->showMessage(m, 4000); });
        connect(s, &StageView::layerChosen, this, [this] { setStage(3); });
    }
    connect(m_paint, &PaintView::allowProgramRequested, m_allowance, &ProgramAllowance::ask);
    connect(m_allowance, &ProgramAllowance::failed, this, &MainWindow::showError);
    connect(m_allowance, &ProgramAllowance::allowed, this, [this](const QString& program) {
        showStatus(tr("Allowed %1; running its layers…").arg(program));
    });
    connect(m_navigate, &NavigateView::tuneRequested, this,
            [this](const std::string& filter, const denoise::ParamValues& params) {
                m_tune->setFilter(filter);
                m_tune->setValues(params);
                setStage(2, false);
            });
    connect(m_compare, &CompareView::openReferenceRequested, m_actions.openReference,
            &QAction::trigger);
    connect(m_stages, &QTabWidget::currentChanged, this, &MainWindow::stageChanged);
    connect(m_filterTabs, &QTabWidget::currentChanged, this, &MainWindow::stageChanged);
    connect(m_region, &RegionOfInterest::changed, this, [this] {
        m_viewer->canvas()->setRegion(QPolygonF(m_region->polygon()));
        // The region is the artist's: the autosave keeps it (not an undo step).
        m_session->record({journal_codec::encodeRegion(m_region->coordinates()), {}, nullptr});
    });
    // The exposure and the channel, as a session file keeps them (Keep Refining's toggle
    // journals the view too).
    connect(m_viewer, &Viewer::exposureChanged, this, [this] { journalView(); });
    connect(m_viewer, &Viewer::channelChanged, this, [this] { journalView(); });
    connect(m_viewer, &Viewer::readoutChanged, m_readout, &ElidedLabel::setFullText);
    connect(m_session, &SessionAdapter::busyChanged, this, [this](bool busy) {
        m_busy->setText(busy ? tr("working…") : QString());
        if (!busy) {
            m_busyProgress->hide();
            m_busyProgress->setRange(0, 1000);
        }
    });
    connect(m_session, &SessionAdapter::progress, this, [this](const QString& what, double f) {
        // At 100 % with work still running (the last of a stage, applying its result) the bar
        // stays, as a busy indicator, until busyChanged(false).
        m_busy->setText(what);
        const bool done = f >= 1.0;
        m_busyProgress->setRange(0, done && m_session->busy() ? 0 : 1000);
        m_busyProgress->setVisible(!done || m_session->busy());
        m_busyProgress->setValue(int(f * 1000.0));
    });
    connect(m_session, &SessionAdapter::loaded, this, [this](const QString& path) {
        m_sessionPath = path;
        m_session->undoStack()->setClean();
        const denoise::Session& s = m_session->session();
        m_document->markSaved();  // a scene is opened again and restored (applyViewState)
        applyViewState(s.viewState);
        m_document->setFinishedFrame(m_session->input());
        updateTitle();
    });
}

void MainWindow::openFile(const QString& path) {
    if (!QFileInfo::exists(path)) {
        showError(tr("Cannot open %1").arg(QFileInfo(path).fileName()),
                  tr("%1: no such file").arg(path));
        return;
    }
    if (!maybeSave([this, path] { openFile(path); })) return;
    addRecentFile(path);
    rebuildRecent();
    if (isSessionPath(path)) {
        m_session->load(path);
        return;
    }
    m_sessionPath.clear();
    m_session->clear();
    m_document->open(path);
}

QString MainWindow::autosaveBase() const {
    return m_options.autosaveBase.isEmpty() ? Autosave::defaultBase() : m_options.autosaveBase;
}

void MainWindow::start(const QString& file, bool offer) {
    // The file first: a question about an old autosave never holds it back.
    if (!file.isEmpty()) openFile(file);
    if (offer) offerRestore(true);
}

void MainWindow::offerRestore(bool ask) {
    const QStringList crashed = Autosave::crashed(autosaveBase());
    if (crashed.isEmpty()) return;
    const QString folder = crashed.first();
    if (!ask) {
        restoreFrom(folder);
        return;
    }
    // Not modal: the studio (and a file opening) goes on while the question waits.
    auto* box = new QMessageBox(
        QMessageBox::Question, tr("Restore your work?"),
        tr("Glint Studio did not exit cleanly last time. Restore the painting and look edits it "
           "autosaved?\n\nNo keeps the autosave aside (File > Recover Autosave… restores it "
           "later); it is not offered again."),
        QMessageBox::Yes | QMessageBox::No, this);
    box->setObjectName(QStringLiteral("restoreQuestion"));
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->setWindowModality(Qt::NonModal);
    box->setDefaultButton(QMessageBox::Yes);
    connect(box, &QMessageBox::finished, this, [this, folder](int answer) {
        if (answer == QMessageBox::Yes) {
            restoreFrom(folder);
            return;
        }
        const QString kept = Autosave::setAside(folder);
        showStatus(kept.isEmpty() ? tr("The autosave was left in %1.").arg(folder)
                                  : tr("The autosave was kept as %1 (File > Recover Autosave… "
                                       "restores it).")
                                        .arg(kept));
    });
    box->show();
}

void MainWindow::restoreFrom(const QString& folder) {
    if (m_autosave->restoring()) return;
    if (!maybeSave([this, folder] { restoreFrom(folder); })) return;
    showStatus(tr("Restoring the autosave…"));
    // Replayed on a worker: the studio keeps drawing, and nothing of it changes until the whole
    // result is in.
    m_autosave->restore(folder, [this, folder](std::shared_ptr<Recovered> recovered,
                                               const QString& error) {
        if (!recovered) {
            const QString kept = Autosave::setAside(folder);
            showError(tr("Cannot restore the autosave"),
                      tr("%1\n\nNothing was changed. The autosave was kept as %2.")
                          .arg(error, kept.isEmpty() ? folder : kept));
            return;
        }
        // This studio's journal becomes the restored one, continued: a second crash replays the
        // same history, which the undo stack then gives back. Where it cannot be moved, the
        // journal records the restored state afresh and the history starts there.
        const bool adopted = m_autosave->journal()->adopt(folder, recovered->edits);
        m_autosave->journal()->setPaused(adopted);
        applyRecovered(*recovered, adopted);
        m_autosave->journal()->setPaused(false);
        if (!adopted) m_autosave->finishRestore(folder);
        const int n = recovered->edits;
        showStatus(recovered->complete ? tr("Restored %1 edits.").arg(n)
                                       : tr("Restored %1 edits (the edit being made at the crash "
                                            "was lost).")
                                             .arg(n));
    });
}

void MainWindow::applyRecovered(Recovered& r, bool withHistory) {
    // Checked on the worker: nothing here can fail halfway. The journal of this studio holds the
    // restored journal (`withHistory`), or records the restored state (file, look, settings,
    // session) afresh: a second crash is covered either way.
    m_restoring = true;
    // One redraw when everything is in (the file, the session and the render each ask for one).
    struct Held {
        Viewer* viewer;
        ~Held() { viewer->holdRedraws(false); }
    } held{m_viewer};
    m_viewer->holdRedraws(true);
    m_sessionPath.clear();
    if (r.file) m_document->adopt(r.path, std::move(*r.file), false);
    for (const LookValue& v : r.look) {
        m_document->setLook(v.item, v.property, v.value, false);
        if (!withHistory)
            m_session->record(
                {journal_codec::encodeSetLook(v.item, v.property, v.value), {}, nullptr});
    }
    if (r.settings) m_document->setSettings(*r.settings);
    if (r.referenceSet) {
        if (r.referenceInfo)
            m_document->restoreReference(*r.referenceInfo, r.reference, false);
        else
            m_document->clearReference();
    }
    if (r.session)
        m_session->install(std::move(*r.session), r.input, r.filterInput, !withHistory);
    else
        m_session->clear();
    if (withHistory) m_session->restoreHistory(r.undo, r.redo, m_document);
    if (m_session->input()) m_document->setFinishedFrame(m_session->input());
    m_region->setCoordinates(r.lasso);  // journalled again by its signal
    if (r.view)
        setView(r.view->exposure, r.view->keepRefining, r.view->stage,
                r.view->channel ? channelFromKey(QString::fromStdString(*r.view->channel))
                                : std::nullopt);
    // What came back is in no file: unsaved until saved, so closing asks first (a clean window
    // would close without asking and drop the autosave, and the restored work with it).
    m_session->undoStack()->resetClean();
    m_restoring = false;
    updateTitle();
}

void MainWindow::showStatus(const QString& message) {
    m_lastStatus = message;
    statusBar()->showMessage(message, 8000);
}

void MainWindow::exportResult(bool exr) {
    if (!m_session->hasSession()) {
        showError(tr("Nothing to export"), tr("Open a scene, an EXR or a session first."));
        return;
    }
    const QString path = askPath(exr ? tr("Export EXR") : tr("Export PNG"),
                                 exr ? tr("OpenEXR (*.exr)") : tr("PNG (*.png)"), true);
    if (path.isEmpty()) return;
    DisplayOptions display;
    display.exposure = float(m_viewer->exposure());
    // Written on a worker.
    m_session->exportResult(path, exr, display, [this, path, exr](const QString& error) {
        if (error.isEmpty())
            statusBar()->showMessage(tr("Wrote %1").arg(path), 4000);
        else
            showError(exr ? tr("Cannot export the EXR") : tr("Cannot export the PNG"), error);
    });
}

QString MainWindow::saveDialogStart(const QString& filter, const QString& suffix) const {
    // The session's folder, else the opened file's, when files can be written there (an asset
    // folder is often read-only), else the user's Documents or home folder.
    QStringList folders;
    for (const QString& file : {m_sessionPath, m_document->path()})
        if (!file.isEmpty()) folders << QFileInfo(file).absolutePath();
    const QString named = m_sessionPath.isEmpty() ? m_document->path() : m_sessionPath;
    const QString name = withFilterExtension(defaultBaseName(named) + suffix,
                                             filter.split(QStringLiteral(";;")).first());
    return QDir(writableFolder(folders)).filePath(name);
}

QString MainWindow::askPath(const QString& title, const QString& filter, bool save,
                            const QString& suffix) {
    if (!save) {
        const QString dir =
            m_document->path().isEmpty() ? QString() : QFileInfo(m_document->path()).path();
        return QFileDialog::getOpenFileName(this, title, dir, filter);
    }
    // The chosen filter's extension when the name lacks it: the file is then of the kind
    // written, and the Open dialog's filter shows it.
    QString chosen = filter.split(QStringLiteral(";;")).first();
    const QString path =
        QFileDialog::getSaveFileName(this, title, saveDialogStart(filter, suffix), filter, &chosen);
    return withFilterExtension(path, chosen);
}

void MainWindow::showError(const QString& title, const QString& message) {
    m_lastError = title + QStringLiteral(": ") + message;
    // Window-modal but not blocking: the studio keeps running (and tests keep driving it).
    auto* box = new QMessageBox(QMessageBox::Warning, title, message, QMessageBox::Ok, this);
    box->setObjectName(QStringLiteral("errorDialog"));
    box->setAttribute(Qt::WA_DeleteOnClose);
    box->setWindowModality(Qt::WindowModal);
    box->open();
    statusBar()->showMessage(title, 6000);
    emit errorShown(title, message);
}

bool MainWindow::maybeSave(std::function<void()> again) {
    if (!isModified() || !m_options.confirmDiscard) return true;
    const auto answer = QMessageBox::question(
        this, tr("Save the session?"),
        tr("The session has unsaved changes (painting, look, render settings or reference)."),
        QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
    if (answer == QMessageBox::Cancel) return false;
    if (answer == QMessageBox::Save) {
        // The save runs on a worker: the action is tried `again` once it succeeded.
        m_afterSave = std::move(again);
        m_actions.saveSession->trigger();
        return false;
    }
    return true;
}

void MainWindow::updateTitle() {
    QString name = m_sessionPath.isEmpty() ? documentTitle(m_document->path())
                                           : QFileInfo(m_sessionPath).fileName();
    if (name.isEmpty()) name = tr("no file");
    setWindowTitle(
        tr("%1%2 — Glint Studio").arg(name, isModified() ? QStringLiteral(" *") : QString()));
}

void MainWindow::rebuildRecent() {
    m_recentMenu->clear();
    for (const QString& f : recentFiles())
        connect(m_recentMenu->addAction(f), &QAction::triggered, this, [this, f] { openFile(f); });
    m_recentMenu->setEnabled(!m_recentMenu->isEmpty());
}

StageView* MainWindow::activeStage() const {
    switch (m_stages->currentIndex()) {
        case 0:
            return m_features;
        case 1:
            return m_regionView;
        case 2:
            return m_filterTabs->currentIndex() == 0 ? static_cast<StageView*>(m_tune) : m_navigate;
        case 3:
            return m_paint;
        default:
            return nullptr;
    }
}

void MainWindow::stageChanged() {
    StageView* next = activeStage();
    if (next == m_activeStage) return;
    m_renderBar->disarmRegionTool();  // a stage change leaves the one-shot render-region tool
    if (m_activeStage) m_activeStage->setActive(false);
    m_activeStage = next;
    if (m_activeStage) m_activeStage->setActive(true);
}

void MainWindow::setStage(int stage, bool navigate) {
    const int before = this->stage();
    if (stage == 2) m_filterTabs->setCurrentIndex(navigate ? 1 : 0);
    m_stages->setCurrentIndex(stage);
    stageChanged();
    if (this->stage() != before) journalView();  // a session file keeps the stage: so does a crash
}

int MainWindow::stage() const {
    return m_stages->currentIndex();
}

void MainWindow::closeEvent(QCloseEvent* event) {
    if (!maybeSave([this] { close(); })) {
        event->ignore();
        return;
    }
    saveWindowState(*this);
    m_document->cancelRender();
    m_autosave->discard();
    event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
    // A file the studio opens (the Open dialog's list); anything else is refused at the door.
    const QList<QUrl> urls = event->mimeData()->urls();
    if (!urls.isEmpty() && urls.first().isLocalFile() && isOpenableFile(urls.first().toLocalFile()))
        event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
    const QList<QUrl> urls = event->mimeData()->urls();
    if (!urls.isEmpty() && urls.first().isLocalFile()) openFile(urls.first().toLocalFile());
}

}  // namespace glint::studio
