// The session's background tools: the magic wand, Poisson diffusion, Auto Start (with the bank
// service), and saving and exporting, each computed on a worker and applied on the UI thread in
// the order asked (docs/studio.md, "What runs where").
#include <atomic>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "model/journal_codec.h"
#include "model/layer_names.h"
#include "model/option_labels.h"
#include "model/session_adapter.h"

namespace glint::studio {

namespace {

// What Auto start says it did: the layers it made and how it estimated each member's error (the
// studio asks for AutoEstimator::Auto, so the image-only estimate means neither half buffers nor
// a variance layer; glint-denoise auto says the same).
QString autoStartSummary(const denoise::AutoResult& result) {
    QString how;
    switch (result.estimator) {
        case denoise::AutoEstimator::Halves:
            how = QObject::tr("cross-validation on the render's halves");
            break;
        case denoise::AutoEstimator::Image:
            how = QObject::tr(
                "SURE with the image-only noise estimate (the render has neither half buffers "
                "nor a variance layer)");
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
                entry.op = journal_codec::encode(journal_codec::Apply{layers});
                entry.images = std::move(*shared);
                emit journal(entry);
                pushEdit(tr("Diffuse the weights"));
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
    // stacking included (its correction becomes a layer of its own).
    m_tasks.run<std::shared_ptr<denoise::AutoResult>>(
        QStringLiteral("auto-start"),
        [this, bank, in, options](const TaskRunner::CancelFlag& cancel) {
            denoise::AutoOptions ao;
            ao.prefilter = options.prefilter;
            ao.prefilterParams = options.prefilterParams;
            ao.progress = progressFor(tr("Auto start: estimating each member's error"), cancel);
            return std::make_shared<denoise::AutoResult>(denoise::autoComposite(*bank, *in, ao));
        },
        [this, generation, bank](std::shared_ptr<denoise::AutoResult> result) {
            // 3. One result layer, one undo step: auto's correction over the composite now
            // (Session::addCorrection) with weight 1 everywhere is auto's result bit for bit,
            // whatever lies beneath; its per-pixel member choice is kept for the choice map.
            whenUnlocked([this, generation, bank, result] {
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
                pushEdit(tr("Auto start"), 2);
                changedAll();
                emit status(autoStartSummary(*result));
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
    emit journal({journal_codec::encode(journal_codec::RenameLayer{index, name}), {}, nullptr});
    pushEdit(tr("Rename layer %1").arg(index + 1));
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
