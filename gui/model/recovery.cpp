#include "model/recovery.h"

#include <QDir>
#include <QFileInfo>
#include <QJsonArray>

#include <map>
#include <variant>

#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "model/edit_text.h"
#include "model/journal.h"
#include "model/journal_codec.h"
#include "model/session_build.h"

namespace glint::studio {

namespace {

// The replay's state: what the studio would hold after the entries so far.
class Replay {
  public:
    Replay(Recovered& out, const denoise::ProgressFn& progress)
        : m_out(out), m_progress(progress) {}

    void apply(const JournalEntry& entry) {
        const QString op = entry.op.value(QStringLiteral("op")).toString();
        if (op == QStringLiteral("open")) {
            // A new file: its own look and settings (a session, when it comes, is journaled).
            m_out.path = entry.op.value(QStringLiteral("path")).toString();
            m_received = entry.frame;  // an image received from a tev client: its pixels
            m_out.look.clear();
            m_settings.reset();
            m_reference.reset();
        } else if (op == QStringLiteral("pixels")) {
            // The received image's client updated it: the latest pixels.
            // An older update's render is removed once the next is written: none to apply.
            if (!m_received)
                throw Error(ErrorKind::Format, "the journal updates pixels of no image");
            if (entry.frame) m_received = entry.frame;
        } else if (op == QStringLiteral("reference")) {
            m_reference = entry;  // decoded at the end, against the look then
        } else if (op == QStringLiteral("look")) {
            const LookValue before = lookValue(entry, "before"), after = lookValue(entry, "after");
            push({0, before, after, lookEditText(after.item, after.property)});
            setLook(*m_steps.back().after);
        } else if (op == QStringLiteral("setLook")) {
            setLook(lookValue(entry, "value"));  // a session file's look: no undo step
        } else if (op == QStringLiteral("region")) {
            m_out.lasso = journal_codec::decodeRegion(entry.op);
        } else if (op == QStringLiteral("view")) {
            m_out.view = journal_codec::decodeView(entry.op);
        } else if (op == QStringLiteral("settings")) {
            m_settings = entry.op;
        } else {
            applySession(entry, journal_codec::decode(entry.op));
        }
    }

    /// The render settings of the last "settings" entry over those of the file (strictly).
    void finishSettings(const render::Settings& base, const std::string& file,
                        const std::string& where) {
        if (!m_settings) return;
        render::Settings s = journal_codec::decodeSettings(*m_settings, base, file, where);
        render::validate(s);
        m_out.settings = s;
    }
    const std::optional<QJsonObject>& settingsEntry() const { return m_settings; }
    /// The last "reference" entry since the file was opened.
    const std::optional<JournalEntry>& referenceEntry() const { return m_reference; }
    /// The undo stack as the journal left it (Recovered::undo, redo).
    void finishHistory() {
        m_out.undo = m_steps;
        m_out.redo = m_redo;
    }
    /// The pixels of the image open when it was received, not read from a file (null: a file).
    const FramePtr& received() const { return m_received; }

  private:
    Recovered& m_out;
    const denoise::ProgressFn& m_progress;
    denoise::SessionOptions m_options;
    std::vector<RestoredStep> m_steps, m_redo;
    std::optional<QJsonObject> m_settings;
    std::optional<JournalEntry> m_reference;
    FramePtr m_received;

    denoise::Session& session() {
        if (!m_out.session)
            throw Error(ErrorKind::Format, "the journal edits a session before starting one");
        return *m_out.session;
    }
    // A new undo step (the redo history goes, as QUndoStack::push drops it).
    void push(RestoredStep step) {
        m_steps.push_back(std::move(step));
        m_redo.clear();
    }
    // The look value a "look" or "setLook" line holds under `key` (checked against the scene
    // at the end).
    static LookValue lookValue(const JournalEntry& entry, const char* key) {
        const QJsonArray a = entry.op.value(QLatin1String(key)).toArray();
        return LookValue{entry.op.value(QStringLiteral("item")).toString().toStdString(),
                         entry.op.value(QStringLiteral("property")).toString().toStdString(),
                         {a.at(0).toDouble(), a.at(1).toDouble(), a.at(2).toDouble()}};
    }
    void setLook(const LookValue& v) {
        for (LookValue& l : m_out.look)
            if (l.item == v.item && l.property == v.property) {
                l.value = v.value;
                return;
            }
        m_out.look.push_back(v);
    }
    Image output(const std::string& filter, const denoise::ParamValues& params) {
        return denoise::applyFilter(denoise::findFilter(filter), *m_out.filterInput, params,
                                    {.region = std::nullopt, .progress = m_progress, .threads = 0});
    }
    static const Image& image(const JournalEntry& entry, std::size_t i) {
        if (i >= entry.images.size())
            throw Error(ErrorKind::Format, "the journal entry lacks its image");
        return entry.images[i];
    }
    static FramePtr frame(const JournalEntry& entry) {
        if (!entry.frame) throw Error(ErrorKind::Format, "the journal entry lacks its render");
        return entry.frame;
    }

    void applySession(const JournalEntry& entry, const journal_codec::Op& op) {
        namespace jc = journal_codec;
        if (const auto* start = std::get_if<jc::Start>(&op)) {
            const FramePtr f = frame(entry);
            m_options = start->options;
            m_out.filterInput = filterInputFor(f, m_options, m_progress);
            std::vector<denoise::LayerSpec> layers = start->layers;
            jc::takeCorrections(layers, entry.images);
            m_out.session = std::make_shared<denoise::Session>(buildSession(
                f, m_out.filterInput, m_options, layers, entry.images, start->names, m_progress));
            m_out.session->bankDir = start->bankDir;
            m_out.input = f;
            m_steps.clear();  // a new session starts the undo history again
            m_redo.clear();
        } else if (std::holds_alternative<jc::Input>(op)) {
            if (!entry.frame) return;  // superseded by a later render (Journal::read)
            denoise::Session& s = session();
            Reapplied out = computeReapply(entry.frame, s.snapshot(), m_progress);
            s.reapply(std::move(*out.prepared));
            m_out.input = entry.frame;
            m_out.filterInput = out.filterInput;
        } else if (const auto* add = std::get_if<jc::AddLayer>(&op)) {
            denoise::Session& s = session();
            const std::size_t index =
                s.addLayer(add->filter, add->params, output(add->filter, add->params));
            if (add->fill) s.fill(index, image(entry, 0), denoise::BrushMode::Add);
            push({add->fill ? 2 : 1, {}, {}, editText(op)});
        } else if (const auto* layers = std::get_if<jc::AddLayers>(&op)) {
            denoise::Session& s = session();
            std::vector<denoise::LayerSpec> specs = layers->layers;
            jc::takeCorrections(specs, entry.images);
            for (std::size_t i = 0; i < specs.size(); ++i) {
                const denoise::LayerSpec& spec = specs[i];
                const Image& weights = image(entry, i);
                const std::size_t index =
                    spec.correction
                        ? s.addCorrection(spec.correction->result, spec.correction->blend)
                        : s.addLayer(spec.filter, spec.params, output(spec.filter, spec.params));
                s.setWeights(index, weights);
            }
            push({2 * int(layers->layers.size()), {}, {}, editText(op)});
        } else if (const auto* remove = std::get_if<jc::RemoveLayer>(&op)) {
            session().removeLayer(remove->index);
            push({1, {}, {}, editText(op)});
        } else if (const auto* rename = std::get_if<jc::RenameLayer>(&op)) {
            session().renameLayer(rename->index, rename->name);
            push({1, {}, {}, editText(op)});
        } else if (const auto* weights = std::get_if<jc::Weights>(&op)) {
            session().setWeights(weights->index, image(entry, 0));
            push({1, {}, {}, editText(op)});
        } else if (const auto* fill = std::get_if<jc::Fill>(&op)) {
            session().fill(fill->index, image(entry, 0), fill->mode);
            push({1, {}, {}, editText(op)});
        } else if (const auto* stroke = std::get_if<jc::Stroke>(&op)) {
            denoise::Session& s = session();
            s.beginStroke(stroke->layer, stroke->brush, stroke->mode);
            for (std::size_t i = 0; i + 1 < stroke->dabs.size(); i += 2)
                s.dab(stroke->dabs[i], stroke->dabs[i + 1]);
            s.endStroke();
            push({1, {}, {}, editText(op)});
        } else if (const auto* apply = std::get_if<jc::Apply>(&op)) {
            session().applyWeights(apply->layers, entry.images);
            push({1, {}, {}, editText(op)});
        } else if (std::holds_alternative<jc::Clear>(op)) {
            m_out.session.reset();
            m_out.input.reset();
            m_out.filterInput.reset();
            m_steps.clear();
            m_redo.clear();
        } else if (std::holds_alternative<jc::Undo>(op)) {
            step(m_steps, m_redo, true);
        } else if (std::holds_alternative<jc::Redo>(op)) {
            step(m_redo, m_steps, false);
        }
    }

    // Undo (or redo) one step of `from`, moved to `to`; nothing to undo does nothing, as on the
    // studio's stack.
    void step(std::vector<RestoredStep>& from, std::vector<RestoredStep>& to, bool undo) {
        if (from.empty()) return;
        RestoredStep s = std::move(from.back());
        from.pop_back();
        if (s.after) setLook(undo ? *s.before : *s.after);
        for (int i = 0; i < s.edits; ++i) {
            if (undo)
                session().undo();
            else
                session().redo();
        }
        to.push_back(std::move(s));
    }
};

}  // namespace

Recovered recover(const QString& folder, const denoise::ProgressFn& progress) {
    Recovered out;
    out.worker = std::this_thread::get_id();
    const std::string journal =
        QDir(folder).filePath(QStringLiteral("journal.jsonl")).toStdString();
    const std::vector<JournalEntry> entries = Journal::read(folder, &out.complete);
    if (entries.empty())
        throw Error(ErrorKind::Format, "the journal holds no edit it can restore", journal);
    Replay replay(out, progress);
    // Each entry names its line when it does not apply.
    auto where = [](std::size_t i, const JournalEntry& entry) {
        return "line " + std::to_string(i + 1) + " (\"" +
               entry.op.value(QStringLiteral("op")).toString().toStdString() + "\")";
    };
    std::size_t settingsLine = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        if (progress && !progress(double(i) / double(entries.size())))
            throw Error(ErrorKind::Cancelled, "the restore was cancelled");
        try {
            replay.apply(entries[i]);
        } catch (const Error& e) {
            if (e.kind() == ErrorKind::Cancelled) throw;
            throw Error(ErrorKind::Format, e.what(), journal, where(i, entries[i]));
        }
        if (entries[i].op.value(QStringLiteral("op")).toString() == QStringLiteral("settings"))
            settingsLine = i;
        ++out.edits;
    }
    replay.finishHistory();
    // The file open at the crash, its look and settings as edited: each checked here, so that
    // applying the result cannot fail halfway.
    render::Settings base;
    if (!out.path.isEmpty()) {
        if (const FramePtr& received = replay.received()) {
            // A received image, as the listener made it the document.
            out.file = std::make_shared<Document::Loaded>();
            out.file->kind = Document::Kind::Exr;
            out.file->frame = received;
        } else if (!QFileInfo::exists(out.path)) {
            throw Error(ErrorKind::Io,
                        "the file the autosave edits no longer exists: " + out.path.toStdString(),
                        journal);
        } else {
            out.file = std::make_shared<Document::Loaded>(Document::load(out.path));
        }
        base = out.file->settings;
        std::vector<render::LookItem> look = out.file->look;
        for (const LookValue& v : out.look) {
            try {
                setLookValue(look, v.item, v.property, v.value, out.path.toStdString());
            } catch (const Error& e) {
                throw Error(ErrorKind::Format, e.what(), journal,
                            "look " + v.item + "/" + v.property);
            }
        }
        // The reference as the journal left it, described against the look restored.
        if (const std::optional<JournalEntry>& ref = replay.referenceEntry()) {
            out.referenceSet = true;
            out.referenceInfo = journal_codec::decodeReference(ref->op, look);
            out.reference = ref->frame;
        }
    } else if (!out.look.empty()) {
        throw Error(ErrorKind::Format, "the journal edits a look before opening a file", journal);
    }
    if (replay.settingsEntry())
        replay.finishSettings(base, journal, where(settingsLine, entries[settingsLine]));
    if (progress) progress(1.0);
    return out;
}

}  // namespace glint::studio
