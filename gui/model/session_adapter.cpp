#include "model/session_adapter.h"

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "model/journal_codec.h"
#include "model/layer_names.h"
#include "model/session_build.h"

namespace glint::studio {

namespace {

bool sameSpecs(const std::vector<denoise::LayerSpec>& a, const std::vector<denoise::LayerSpec>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
        if (a[i].filter != b[i].filter || a[i].params != b[i].params) return false;
    return true;
}

}  // namespace

SessionAdapter::SessionAdapter(QObject* parent) : QObject(parent) {
    connect(&m_tasks, &TaskRunner::busyChanged, this, [this] { emit busyChanged(busy()); });
}

SessionAdapter::~SessionAdapter() {
    // Commands point at this adapter: drop them first, silently: the window listening to the
    // stack's signals may be half destroyed already (UBSan caught a call into it).
    m_undo.blockSignals(true);
    m_undo.clear();
}

void SessionAdapter::whenUnlocked(std::function<void()> fn) {
    if (!m_locked)
        fn();
    else
        m_afterUnlock.push_back(std::move(fn));
}

void SessionAdapter::lock() {
    if (m_readers++ > 0) return;
    m_locked = true;
    emit lockedChanged(true);
}

void SessionAdapter::unlock() {
    if (--m_readers > 0) return;
    m_locked = false;
    emit lockedChanged(false);
    std::vector<std::function<void()>> queued;
    queued.swap(m_afterUnlock);
    for (auto& fn : queued) fn();
}

void SessionAdapter::changedAll() {
    ++m_revision;
    if (m_session) emit compositeChanged(Rect{0, m_session->width(), 0, m_session->height()});
    emit layersChanged();
}

denoise::ProgressFn SessionAdapter::progressFor(const QString& what,
                                                const TaskRunner::CancelFlag& cancel) {
    // Called on a worker thread: progress is posted to the UI thread, at most every 1 %.
    auto last = std::make_shared<std::atomic<int>>(-1);
    return [this, what, cancel, last](double fraction) {
        const int percent = int(fraction * 100.0);
        if (percent != last->exchange(percent))
            QMetaObject::invokeMethod(
                &m_tasks, [this, what, fraction] { emit progress(what, fraction); },
                Qt::QueuedConnection);
        return !cancel->load();
    };
}

void SessionAdapter::setInput(FramePtr frame, bool journal) {
    if (!frame) return;
    if (!m_session || m_session->layerCount() == 0) {
        startSession(frame, {}, {});
        return;
    }
    if (frame->width() != m_session->width() || frame->height() != m_session->height()) {
        // Never drop the painting silently: the user saves it or starts a new session.
        emit failed(tr("The render changed size"),
                    tr("The new render is %1x%2, the painted session %3x%4. The session is kept; "
                       "save it, or choose File > New Session to paint on the new render.")
                        .arg(frame->width())
                        .arg(frame->height())
                        .arg(m_session->width())
                        .arg(m_session->height()));
        return;
    }
    m_pendingInput = frame;
    m_pendingJournal = journal;
    if (m_session->inStroke()) return;  // installed when the stroke ends
    reapplyInBackground();
}

void SessionAdapter::rerunLayers() {
    // Not journalled: the same render, and a restore runs the layers anyway.
    if (m_session && m_input && m_session->layerCount() > 0) setInput(m_input, false);
}

void SessionAdapter::startSession(FramePtr frame, std::vector<denoise::LayerSpec> carry,
                                  std::vector<Image> carryWeights,
                                  std::vector<std::string> carryNames) {
    ++m_generation;
    const denoise::SessionOptions options = m_options;
    JournalEntry entry;
    // The new session names the bank folder of the present one.
    const std::string bankDir = m_session ? m_session->bankDir.string() : std::string();
    entry.op = journal_codec::encode(journal_codec::Start{options, carry, carryNames, bankDir});
    entry.images = carryWeights;
    for (Image& image : journal_codec::correctionImages(carry))
        entry.images.push_back(std::move(image));
    entry.frame = frame;
    struct Started {
        std::shared_ptr<denoise::Session> session;
        FramePtr filterInput;
    };
    m_tasks.run<Started>(
        QStringLiteral("session"),
        [this, frame, options, carry, carryWeights,
         carryNames](const TaskRunner::CancelFlag& cancel) {
            const denoise::ProgressFn progress = progressFor(tr("Preparing the session"), cancel);
            // The session copies the render (about 100 MB at 1024², features included): here,
            // not on the UI thread.
            FramePtr in = filterInputFor(frame, options, progress);
            return Started{std::make_shared<denoise::Session>(buildSession(
                               frame, in, options, carry, carryWeights, carryNames, progress)),
                           in};
        },
        [this, frame, entry, bankDir](Started started) {
            m_undo.clear();
            // The new session names the same bank folder (m_bankFolder stays).
            started.session->bankDir = bankDir;
            m_session = std::move(started.session);
            m_input = frame;
            m_filterInput = started.filterInput;
            m_banks.setFrame(m_input);
            emit journal(entry);
            emit sessionReset();
            emit inputChanged();
            changedAll();
        },
        [this](const QString& message) { emit failed(tr("Cannot start the session"), message); });
}

void SessionAdapter::reapplyInBackground() {
    FramePtr frame = m_pendingInput;
    const bool journal = m_pendingJournal;
    m_pendingInput.reset();
    if (!frame || !m_session) return;
    auto snapshot = std::make_shared<const denoise::Session::Snapshot>(m_session->snapshot());
    m_tasks.run<std::shared_ptr<Reapplied>>(
        QStringLiteral("reapply"),
        [this, frame, snapshot](const TaskRunner::CancelFlag& cancel) {
            return std::make_shared<Reapplied>(computeReapply(
                frame, *snapshot, progressFor(tr("Re-applying the layers"), cancel)));
        },
        [this, frame, journal](std::shared_ptr<Reapplied> out) {
            whenUnlocked([this, frame, out, journal] { installReapply(frame, *out, journal); });
        },
        [this](const QString& message) {
            emit failed(tr("Cannot re-apply the layers to the new render"), message);
        });
}

void SessionAdapter::installReapply(FramePtr frame, Reapplied& reapplied, bool journal) {
    if (!m_session) return;
    if (m_session->inStroke() || !sameSpecs(reapplied.prepared->specs, m_session->layerSpecs())) {
        // The layers changed meanwhile (or a stroke is open): compute again.
        m_pendingInput = frame;
        m_pendingJournal = journal;
        if (!m_session->inStroke()) reapplyInBackground();
        return;
    }
    ++m_generation;
    // Moves and pointer swaps (the composite is rebuilt here only if the weights changed since
    // the snapshot).
    m_session->reapply(std::move(*reapplied.prepared));
    m_input = frame;
    m_filterInput = reapplied.filterInput;
    m_banks.setFrame(m_input);
    if (journal) {
        JournalEntry entry;
        entry.op = journal_codec::encode(journal_codec::Input{});
        entry.frame = frame;
        emit this->journal(entry);
    }
    emit inputChanged();
    changedAll();
}

namespace {

// The session's current layers as a new session carries them over (auto's correction with its
// images), their weights and names.
struct Carried {
    std::vector<denoise::LayerSpec> specs;
    std::vector<Image> weights;
    std::vector<std::string> names;
};

Carried carriedLayers(const denoise::Session& session) {
    Carried c;
    for (std::size_t i = 0; i < session.layerCount(); ++i) {
        const denoise::SessionLayer& l = session.layer(i);
        c.specs.emplace_back(l.filter, l.params, l.correction);
        c.weights.push_back(l.weights);
        c.names.push_back(l.name);
    }
    return c;
}

}  // namespace

void SessionAdapter::setOptions(const denoise::SessionOptions& options) {
    m_options = options;
    if (!m_session) return;
    Carried c = carriedLayers(*m_session);
    startSession(m_input, std::move(c.specs), std::move(c.weights), std::move(c.names));
}

void SessionAdapter::pushEdit(const QString& text, int steps) {
    ++m_revision;
    m_undo.push(new SessionCommand(this, text, steps));
}

void SessionAdapter::doAddLayer(const std::string& filter, const denoise::ParamValues& params,
                                Image output, const std::optional<Image>& fillMask) {
    const std::size_t index = m_session->addLayer(filter, params, std::move(output));
    int steps = 1;
    Rect changed{};
    if (fillMask) {
        changed = m_session->fill(index, *fillMask, denoise::BrushMode::Add);
        ++steps;
    }
    JournalEntry entry;
    entry.op = journal_codec::encode(
        journal_codec::AddLayer{filter, m_session->layer(index).params, bool(fillMask)});
    if (fillMask) entry.images.push_back(*fillMask);
    emit journal(entry);
    pushEdit(tr("Add %1").arg(layerName(filter, m_session->layer(index).params)), steps);
    emit layersChanged();
    if (!changed.empty()) emit compositeChanged(changed);
}

void SessionAdapter::addLayer(const std::string& filter, const denoise::ParamValues& params,
                              std::optional<Image> fillMask) {
    if (!m_session) return;
    const denoise::Filter* f = &denoise::findFilter(filter);
    const denoise::ParamValues resolved = denoise::resolveParams(*f, params);
    runAddLayer(
        [this, f, filter, resolved](const FrameBuffers& in, const TaskRunner::CancelFlag& cancel) {
            return NewLayer{filter, resolved,
                            std::make_shared<Image>(denoise::applyFilter(
                                *f, in, resolved,
                                {.region = std::nullopt,
                                 .progress = progressFor(tr("Adding a layer"), cancel),
                                 .threads = 0}))};
        },
        std::move(fillMask));
}

void SessionAdapter::addChosenLayer(
    std::function<std::pair<std::string, denoise::ParamValues>(const FrameBuffers&)> choose,
    std::optional<Image> fillMask) {
    if (!m_session) return;
    runAddLayer(
        [this, choose](const FrameBuffers& in, const TaskRunner::CancelFlag& cancel) {
            const auto [filter, chosen] = choose(in);
            if (filter.empty()) return NewLayer{};
            const denoise::Filter& f = denoise::findFilter(filter);
            const denoise::ParamValues params = denoise::resolveParams(f, chosen);
            return NewLayer{filter, params,
                            std::make_shared<Image>(denoise::applyFilter(
                                f, in, params,
                                {.region = std::nullopt,
                                 .progress = progressFor(tr("Adding a layer"), cancel),
                                 .threads = 0}))};
        },
        std::move(fillMask));
}

void SessionAdapter::runAddLayer(
    std::function<NewLayer(const FrameBuffers&, const TaskRunner::CancelFlag&)> work,
    std::optional<Image> fillMask) {
    FramePtr in = m_filterInput;
    const std::uint64_t generation = m_generation;
    m_tasks.run<NewLayer>(
        QStringLiteral("add-%1").arg(m_revision),
        [work, in](const TaskRunner::CancelFlag& cancel) { return work(*in, cancel); },
        [this, work, fillMask, generation](NewLayer layer) {
            if (!layer.output) return;
            whenUnlocked([this, work, fillMask, generation, layer] {
                if (!m_session) return;
                if (generation != m_generation) {
                    // A new render arrived meanwhile: the output must be of the new one.
                    runAddLayer(work, fillMask);
                    return;
                }
                try {
                    doAddLayer(layer.filter, layer.params, std::move(*layer.output), fillMask);
                } catch (const Error& e) {
                    emit failed(tr("Cannot add the layer"), QString::fromStdString(e.what()));
                }
            });
        },
        [this](const QString& message) { emit failed(tr("Cannot add the layer"), message); });
}

void SessionAdapter::removeLayer(std::size_t index) {
    if (!m_session || m_locked) return;
    m_session->removeLayer(index);
    emit journal({journal_codec::encode(journal_codec::RemoveLayer{index}), {}, nullptr});
    pushEdit(tr("Remove layer %1").arg(index + 1));
    changedAll();
}

void SessionAdapter::setWeights(std::size_t index, const Image& weights) {
    if (!m_session || m_locked) return;
    m_session->setWeights(index, weights);
    emit journal({journal_codec::encode(journal_codec::Weights{index}), {weights}, nullptr});
    pushEdit(tr("Set the weights of layer %1").arg(index + 1));
    changedAll();
}

void SessionAdapter::fill(std::size_t index, const Image& mask, denoise::BrushMode mode) {
    if (!m_session || m_locked) return;
    const Rect changed = m_session->fill(index, mask, mode);
    emit journal({journal_codec::encode(journal_codec::Fill{index, mode}), {mask}, nullptr});
    pushEdit(tr("Fill layer %1").arg(index + 1));
    emit weightsChanged();
    if (!changed.empty()) emit compositeChanged(changed);
}

void SessionAdapter::beginStroke(std::size_t layer, const denoise::Brush& brush,
                                 denoise::BrushMode mode) {
    if (!m_session || m_locked || m_session->inStroke()) return;
    m_session->beginStroke(layer, brush, mode);
    m_strokeBefore = m_session->layer(layer).weights;
    m_stroke = {layer, brush, mode, {}};
}

Rect SessionAdapter::dab(double x, double y) {
    if (!m_session || !m_session->inStroke()) return {};
    const Rect r = m_session->dab(x, y);
    m_stroke.dabs.push_back(x);
    m_stroke.dabs.push_back(y);
    if (!r.empty()) {
        ++m_revision;
        emit compositeChanged(r);
    }
    return r;
}

void SessionAdapter::endStroke() {
    if (!m_session || !m_session->inStroke()) return;
    const std::size_t layer = m_stroke.layer;
    m_session->endStroke();
    // The session records nothing for a stroke that changed nothing: neither do we.
    const Image& after = m_session->layer(layer).weights;
    const bool changed =
        !std::equal(after.data().begin(), after.data().end(), m_strokeBefore.data().begin());
    m_strokeBefore = Image();
    if (changed) {
        emit journal({journal_codec::encode(m_stroke), {}, nullptr});
        pushEdit(tr("Stroke on layer %1").arg(layer + 1));
        emit weightsChanged();
    }
    if (m_pendingInput) reapplyInBackground();
}

void SessionAdapter::load(const QString& path) {
    const std::filesystem::path file(path.toStdString());
    struct Loaded {
        std::shared_ptr<denoise::Session> session;
        FramePtr input, filterInput;
    };
    m_tasks.run<Loaded>(
        QStringLiteral("session"),
        [this, file](const TaskRunner::CancelFlag& cancel) {
            auto session = std::make_shared<denoise::Session>(
                denoise::Session::load(file, progressFor(tr("Loading the session"), cancel)));
            // Shared copies of the render for the views, made here rather than on the UI thread.
            FramePtr input = std::make_shared<const FrameBuffers>(session->input());
            FramePtr filterInput =
                session->options().prefilter
                    ? std::make_shared<const FrameBuffers>(session->filterInput())
                    : input;
            return Loaded{session, input, filterInput};
        },
        [this, path](Loaded result) {
            install(std::move(*result.session), result.input, result.filterInput);
            emit loaded(path);
        },
        [this, path](const QString& message) {
            emit failed(tr("Cannot open the session %1").arg(path), message);
        });
}

void SessionAdapter::install(denoise::Session session, FramePtr input, FramePtr filterInput) {
    ++m_generation;
    m_undo.clear();
    m_options = session.options();
    m_input = input ? input : std::make_shared<const FrameBuffers>(session.input());
    m_filterInput = filterInput ? filterInput
                    : m_options.prefilter
                        ? std::make_shared<const FrameBuffers>(session.filterInput())
                        : m_input;
    m_session = std::make_shared<denoise::Session>(std::move(session));
    m_banks.setFrame(m_input);
    // The bank folder the session names gives the studio's banks its filters and their fixed
    // parameters (a folder that cannot be read gives none, and says so).
    m_bankFolder = {};
    if (!m_session->bankDir.empty()) {
        try {
            m_bankFolder = denoise::readBankOptions(m_session->bankDir);
        } catch (const Error& e) {
            emit status(tr("The session's bank folder cannot be read, so the banks use the "
                           "studio's filters: %1")
                            .arg(QString::fromStdString(e.what())));
        }
    }
    // The journal starts again from this session: its input and its layers with their weights
    // (auto's correction with its images).
    Carried c = carriedLayers(*m_session);
    JournalEntry entry;
    entry.images = std::move(c.weights);
    for (Image& image : journal_codec::correctionImages(c.specs))
        entry.images.push_back(std::move(image));
    entry.op = journal_codec::encode(
        journal_codec::Start{m_options, c.specs, std::move(c.names), m_session->bankDir.string()});
    entry.frame = m_input;
    emit journal(entry);
    emit sessionReset();
    emit inputChanged();
    changedAll();
}

void SessionAdapter::clear() {
    m_tasks.cancel(QStringLiteral("reapply"));
    // An Auto Start waiting for its bank is of the dropped session.
    if (m_autoStartTicket != 0) {
        m_banks.withdraw(m_autoStartTicket);
        m_autoStartTicket = 0;
        emit busyChanged(busy());
    }
    m_undo.clear();
    m_session.reset();
    m_bankFolder = {};
    m_input.reset();
    m_filterInput.reset();
    m_banks.setFrame(nullptr);
    m_pendingInput.reset();
    ++m_generation;
    // A restore must not carry the dropped session over to the next file.
    emit journal({journal_codec::encode(journal_codec::Clear{}), {}, nullptr});
    emit sessionReset();
    emit layersChanged();
}

SessionCommand::SessionCommand(SessionAdapter* adapter, const QString& text, int steps)
    : QUndoCommand(text), m_adapter(adapter), m_steps(steps) {}

void SessionCommand::undo() {
    for (int i = 0; i < m_steps; ++i) m_adapter->m_session->undo();
    m_adapter->record({journal_codec::encode(journal_codec::Undo{}), {}, nullptr});
    m_adapter->changedAll();
}

void SessionCommand::redo() {
    if (m_first) {
        m_first = false;  // the session did it already
        return;
    }
    for (int i = 0; i < m_steps; ++i) m_adapter->m_session->redo();
    m_adapter->record({journal_codec::encode(journal_codec::Redo{}), {}, nullptr});
    m_adapter->changedAll();
}

}  // namespace glint::studio
