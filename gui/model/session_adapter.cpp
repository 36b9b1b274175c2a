#include "model/session_adapter.h"

#include <atomic>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "model/edit_text.h"
#include "model/journal_codec.h"
#include "model/look_command.h"
#include "model/option_labels.h"
#include "model/recovery.h"
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

void SessionAdapter::pushEdit(const journal_codec::Op& op, int steps) {
    ++m_revision;
    m_undo.push(new SessionCommand(this, editText(op), steps));
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
    const journal_codec::AddLayer added{filter, m_session->layer(index).params, bool(fillMask)};
    JournalEntry entry;
    entry.op = journal_codec::encode(added);
    if (fillMask) entry.images.push_back(*fillMask);
    emit journal(entry);
    pushEdit(added, steps);
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
    const journal_codec::RemoveLayer removed{index};
    emit journal({journal_codec::encode(removed), {}, nullptr});
    pushEdit(removed);
    changedAll();
}

void SessionAdapter::setWeights(std::size_t index, Image weights) {
    if (!m_session || m_locked) return;
    m_session->setWeights(index, weights);
    const journal_codec::Weights set{index};
    JournalEntry entry{journal_codec::encode(set), {}, nullptr};
    entry.images.push_back(std::move(weights));
    emit journal(entry);
    pushEdit(set);
    changedAll();
}

void SessionAdapter::fill(std::size_t index, const Image& mask, denoise::BrushMode mode) {
    if (!m_session || m_locked) return;
    const Rect changed = m_session->fill(index, mask, mode);
    const journal_codec::Fill filled{index, mode};
    emit journal({journal_codec::encode(filled), {mask}, nullptr});
    pushEdit(filled);
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
        pushEdit(m_stroke);
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

void SessionAdapter::install(denoise::Session session, FramePtr input, FramePtr filterInput,
                             bool journalled) {
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
    if (journalled) {
        // The journal starts again from this session: its input and its layers with their
        // weights (auto's correction with its images).
        Carried c = carriedLayers(*m_session);
        JournalEntry entry;
        entry.images = std::move(c.weights);
        for (Image& image : journal_codec::correctionImages(c.specs))
            entry.images.push_back(std::move(image));
        entry.op = journal_codec::encode(journal_codec::Start{
            m_options, c.specs, std::move(c.names), m_session->bankDir.string()});
        entry.frame = m_input;
        emit journal(entry);
    }
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

void SessionAdapter::restoreHistory(const std::vector<RestoredStep>& done,
                                    const std::vector<RestoredStep>& undone, Document* document) {
    // Every step pushed as done (a push's redo does nothing now), the undone ones with the next
    // redo on top, then the stack's index set back over them: the commands do nothing meanwhile,
    // as the session already holds every edit in its own history.
    m_restoringHistory = true;
    auto command = [&](const RestoredStep& step) -> QUndoCommand* {
        if (step.after)
            return new LookCommand(document, this, step.after->item, step.after->property,
                                   step.before->value, step.after->value);
        return new SessionCommand(this, step.text, step.edits);
    };
    for (const RestoredStep& step : done) m_undo.push(command(step));
    for (auto it = undone.rbegin(); it != undone.rend(); ++it) m_undo.push(command(*it));
    m_undo.setIndex(int(done.size()));
    m_restoringHistory = false;
}

void SessionCommand::undo() {
    if (m_adapter->m_restoringHistory) return;
    for (int i = 0; i < m_steps; ++i) m_adapter->m_session->undo();
    m_adapter->record({journal_codec::encode(journal_codec::Undo{}), {}, nullptr});
    m_adapter->changedAll();
}

void SessionCommand::redo() {
    if (m_first || m_adapter->m_restoringHistory) {
        m_first = false;  // the session did it already
        return;
    }
    for (int i = 0; i < m_steps; ++i) m_adapter->m_session->redo();
    m_adapter->record({journal_codec::encode(journal_codec::Redo{}), {}, nullptr});
    m_adapter->changedAll();
}

// The session's background tools: the magic wand, Poisson diffusion, Auto Start (with the bank
// service), and saving and exporting, each computed on a worker and applied on the UI thread in
// the order asked (docs/lab/studio.md, "How it is built").

namespace {

// What Auto start says it did: the layers it made and how it estimated each member's error (the
// studio asks for AutoEstimator::Auto, so the image-only estimate means neither half buffers nor
// a variance layer; glint-denoise auto says the same).
QString autoStartSummary(const denoise::AutoResult& result, bool denoised) {
    QString how;
    switch (result.estimator) {
        case denoise::AutoEstimator::Halves:
            how = QObject::tr("cross-validation on the render's halves");
            break;
        case denoise::AutoEstimator::Image:
            how = denoised ? QObject::tr(
                                 "SURE with the image-only noise estimate (the image is already "
                                 "denoised: its half buffers and variance are the render's)")
                           : QObject::tr(
                                 "SURE with the image-only noise estimate (the render has neither "
                                 "half buffers nor a variance layer)");
            break;
        default:
            how = QObject::tr("SURE with the render's variance");
            break;
    }
    return QObject::tr("Auto start: one result layer blending %n member(s), errors estimated by %1",
                       "", int(result.layers.size()))
        .arg(how);
}

}  // namespace

void SessionAdapter::wand(std::size_t layer, int x, int y, const denoise::WandOptions& options,
                          denoise::BrushMode mode) {
    if (!m_session || m_locked || !m_filterInput) return;
    FramePtr in = m_filterInput;
    if (x < 0 || y < 0 || x >= in->width() || y >= in->height()) return;
    const denoise::Session* session = m_session.get();
    // The masks are computed on workers and filled in the order of the clicks.
    const std::uint64_t seq = m_wandNext++;
    auto ready = [this, seq](std::function<void()> fill) {
        m_wandReady[seq] = std::move(fill);
        for (auto it = m_wandReady.find(m_wandApplied); it != m_wandReady.end();
             it = m_wandReady.find(m_wandApplied)) {
            std::function<void()> next = std::move(it->second);
            m_wandReady.erase(it);
            ++m_wandApplied;
            whenUnlocked(std::move(next));
        }
    };
    m_tasks.run<std::shared_ptr<Image>>(
        QStringLiteral("wand-%1").arg(seq),
        [in, x, y, options](const TaskRunner::CancelFlag&) {
            Image seeds(in->width(), in->height(), 1, 0.0f);
            seeds(x, y, 0) = 1.0f;
            return std::make_shared<Image>(denoise::magicWand(*in, seeds, options));
        },
        [this, ready, session, layer, mode](std::shared_ptr<Image> mask) {
            ready([this, session, layer, mode, mask] {
                if (m_session.get() != session || layer >= m_session->layerCount()) return;
                emit wandSelected(mask);
                fill(layer, *mask, mode);
            });
        },
        [this, ready](const QString& message) {
            ready([] {});
            emit failed(tr("The magic wand failed"), message);
        });
}

void SessionAdapter::diffuse(const std::vector<std::size_t>& layers) {
    if (!m_session || m_locked || m_session->inStroke()) return;
    // The session is read on the worker: it is locked (nothing edits it) until the maps are back.
    std::shared_ptr<const denoise::Session> session = m_session;
    lock();
    emit progress(tr("Diffusing the weights"), 0.0);
    m_tasks.run<std::vector<Image>>(
        QStringLiteral("diffuse"),
        [session, layers](const TaskRunner::CancelFlag&) { return session->diffusionMaps(layers); },
        [this, session, layers](std::vector<Image> maps) {
            emit progress(tr("Diffusing the weights"), 1.0);
            auto shared = std::make_shared<std::vector<Image>>(std::move(maps));
            // Applied once no other worker reads the session (a save may).
            whenUnlocked([this, session, layers, shared] {
                if (m_session != session) return;
                m_session->applyWeights(layers, *shared);
                JournalEntry entry;
                const journal_codec::Apply applied{layers};
                entry.op = journal_codec::encode(applied);
                entry.images = std::move(*shared);
                emit journal(entry);
                pushEdit(applied);
                changedAll();
            });
            unlock();
        },
        [this](const QString& message) {
            unlock();
            emit failed(tr("Poisson diffusion failed"), message);
        });
}

void SessionAdapter::readInBackground(const QString& what,
                                      std::function<void(const denoise::Session&)> read,
                                      std::function<void(const QString&)> done) {
    // The session is locked (edits wait, painting is refused) while the worker reads it.
    std::shared_ptr<const denoise::Session> session = m_session;
    lock();
    emit progress(what, 0.0);
    m_tasks.run<bool>(
        QStringLiteral("read-%1").arg(m_reads++),
        [session, read](const TaskRunner::CancelFlag&) {
            read(*session);
            return true;
        },
        [this, what, done](bool) {
            emit progress(what, 1.0);
            unlock();
            if (done) done(QString());
        },
        [this, what, done](const QString& message) {
            emit progress(what, 1.0);
            unlock();
            if (done) done(message);
        });
}

denoise::BankOptions SessionAdapter::bankOptions(int size,
                                                 const std::optional<Rect>& region) const {
    return studioBankOptions(size, region, m_options, m_bankFolder);
}

void SessionAdapter::autoStart(int bankSize) {
    if (!m_session || m_locked) return;
    FramePtr in = m_input;
    const denoise::SessionOptions options = m_options;
    const std::uint64_t generation = m_generation;
    // 1. The bank of the input, from the bank service (Navigate may have built it already).
    const denoise::BankOptions bo = bankOptions(bankSize);
    m_banks.withdraw(m_autoStartTicket);
    m_tasks.cancel(QStringLiteral("auto-start"));
    const bool wasBusy = busy();
    m_autoStartTicket = m_banks.request(
        in, bo, this,
        {[this, in, options, generation](BankService::BankPtr bank) {
             m_autoStartTicket = 0;
             autoChoose(std::move(bank), in, options, generation);
         },
         [this](double f) { emit progress(tr("Auto start: building the bank"), f); },
         [this](const QString& message) {
             m_autoStartTicket = 0;
             if (!busy()) emit busyChanged(false);
             emit failed(tr("Auto start failed"), message);
         }});
    if (!wasBusy) emit busyChanged(true);
}

void SessionAdapter::autoChoose(BankService::BankPtr bank, FramePtr in,
                                const denoise::SessionOptions& options, std::uint64_t generation) {
    // 2. The per-pixel choice among the members, on a worker: glint-denoise auto's defaults,
    // stacking included (its correction becomes a layer of its own). An image already denoised
    // (glint-final's or glint-denoise's output) keeps the render's halves and variance, which do
    // not describe its colour: there the image alone gives the noise.
    const bool denoised = denoise::colourIsDenoised(*in);
    m_tasks.run<std::shared_ptr<denoise::AutoResult>>(
        QStringLiteral("auto-start"),
        [this, bank, in, options, denoised](const TaskRunner::CancelFlag& cancel) {
            denoise::AutoOptions ao;
            if (denoised) ao.estimator = denoise::AutoEstimator::Image;
            ao.prefilter = options.prefilter;
            ao.prefilterParams = options.prefilterParams;
            ao.progress = progressFor(tr("Auto start: estimating each member's error"), cancel);
            return std::make_shared<denoise::AutoResult>(denoise::autoComposite(*bank, *in, ao));
        },
        [this, generation, bank, denoised](std::shared_ptr<denoise::AutoResult> result) {
            // 3. One result layer, one undo step: auto's correction over the composite now
            // (Session::addCorrection) with weight 1 everywhere is auto's result bit for bit,
            // whatever lies beneath; its per-pixel member choice is kept for the choice map.
            whenUnlocked([this, generation, bank, result, denoised] {
                if (!m_session || generation != m_generation) return;  // a new render came
                std::size_t index = 0;
                try {
                    index = m_session->addCorrection(result->composite);
                    m_session->setWeights(index,
                                          Image(m_session->width(), m_session->height(), 1, 1.0f));
                } catch (const Error& e) {
                    emit failed(tr("Auto start failed"), QString::fromStdString(e.what()));
                    return;
                }
                const denoise::SessionLayer& layer = m_session->layer(index);
                AutoChoiceMap map;
                map.choice = std::make_shared<const Image>(result->choice);
                std::vector<OptionMember> members;
                for (const denoise::BankMember& m : bank->members())
                    members.push_back({m.filter, m.params});
                map.members = distinctNames(members);
                map.used = int(result->layers.size());
                m_autoChoices.emplace_back(layer.correction, std::move(map));
                // One journal entry, as it is one undo step (a restore replays it).
                journal_codec::AddLayers added;
                added.layers.emplace_back(layer.filter, layer.params, layer.correction);
                JournalEntry entry;
                entry.images.push_back(layer.weights);
                for (Image& image : journal_codec::correctionImages(added.layers))
                    entry.images.push_back(std::move(image));
                entry.op = journal_codec::encode(added);
                emit journal(entry);
                pushEdit(added, 2);
                changedAll();
                emit status(autoStartSummary(*result, denoised));
            });
        },
        [this](const QString& message) { emit failed(tr("Auto start failed"), message); });
}

const SessionAdapter::AutoChoiceMap* SessionAdapter::autoChoice(std::size_t index) const {
    if (!m_session || index >= m_session->layerCount()) return nullptr;
    const auto& correction = m_session->layer(index).correction;
    if (!correction) return nullptr;
    for (const auto& [layer, map] : m_autoChoices)
        if (layer.lock() == correction) return &map;
    return nullptr;
}

void SessionAdapter::renameLayer(std::size_t index, const std::string& name) {
    if (!m_session || m_locked || m_session->inStroke() || index >= m_session->layerCount() ||
        m_session->layer(index).name == name)
        return;
    m_session->renameLayer(index, name);
    const journal_codec::RenameLayer renamed{index, name};
    emit journal({journal_codec::encode(renamed), {}, nullptr});
    pushEdit(renamed);
    emit layersChanged();
}

void SessionAdapter::save(const QString& path, const std::optional<Rect>& region,
                          const std::map<std::string, std::string>& viewState,
                          const std::map<std::string, FramePtr>& frames,
                          std::function<void(const QString&)> done) {
    if (!m_session) throw Error(ErrorKind::InvalidArgument, "there is no session to save");
    m_session->region = region;
    m_session->viewState = viewState;
    m_session->sideFrames = {frames.begin(), frames.end()};  // shared, not copied
    const std::filesystem::path file(path.toStdString());
    // Session::save writes to a temporary name and renames: a failed save leaves the old file.
    readInBackground(
        tr("Saving the session"), [file](const denoise::Session& s) { s.save(file); },
        std::move(done));
}

void SessionAdapter::exportResult(const QString& path, bool exr, const DisplayOptions& display,
                                  std::function<void(const QString&)> done) {
    if (!m_session) throw Error(ErrorKind::InvalidArgument, "there is no session to export");
    const std::filesystem::path file(path.toStdString());
    readInBackground(
        tr("Exporting the result"),
        [file, exr, display](const denoise::Session& s) {
            if (exr)
                s.exportExr(file);
            else
                s.exportPng(file, display);
        },
        std::move(done));
}

}  // namespace glint::studio
