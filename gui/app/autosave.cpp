#include "app/autosave.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QStandardPaths>
#include <QTimer>
#include <memory>

#include <signal.h>
#include <unistd.h>

#include "glint/image/error.h"
#include "model/journal_codec.h"
#include "model/look_command.h"

namespace glint::studio {

namespace {

bool processAlive(qint64 pid) {
    return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

}  // namespace

Autosave::Autosave(const QString& base, SessionAdapter* session, QObject* parent)
    : QObject(parent), m_session(session) {
    const QString folder = QDir(base).filePath(QString::number(QCoreApplication::applicationPid()));
    m_journal = std::make_unique<Journal>(folder);
    connect(session, &SessionAdapter::journal, this,
            [this](const JournalEntry& entry) { m_journal->append(entry); });
}

Autosave::~Autosave() = default;

QString Autosave::defaultBase() {
    const QByteArray env = qgetenv("GLINT_STUDIO_AUTOSAVE");
    if (!env.isEmpty()) return QString::fromLocal8Bit(env);
    return QDir(QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation))
        .filePath(QStringLiteral("autosave"));
}

QStringList Autosave::crashed(const QString& base) {
    QStringList out;
    const QFileInfoList folders =
        QDir(base).entryInfoList(QDir::Dirs | QDir::NoDotAndDotDot, QDir::Time);
    for (const QFileInfo& f : folders) {
        bool ok = false;
        const qint64 pid = f.fileName().toLongLong(&ok);
        if (!ok || pid == QCoreApplication::applicationPid() || processAlive(pid)) continue;
        if (QFileInfo::exists(QDir(f.filePath()).filePath(QStringLiteral("journal.jsonl"))))
            out << f.filePath();
    }
    return out;
}

void Autosave::recordOpen(const QString& path) {
    JournalEntry entry;
    entry.op = {{QStringLiteral("op"), QStringLiteral("open")},
                {QStringLiteral("path"), QFileInfo(path).absoluteFilePath()}};
    m_journal->append(entry);
}

void Autosave::watch(Document* document) {
    connect(document, &Document::settingsChanged, this, [this, document] {
        m_journal->append({journal_codec::encodeSettings(document->settings()), {}, nullptr});
    });
    connect(document, &Document::referenceChanged, this, [this, document] {
        if (document->reference() == m_journalledReference) return;  // a render of one started
        m_journalledReference = document->reference();
        const std::optional<ReferenceInfo>& info = document->referenceInfo();
        const bool rendered = info && info->source == ReferenceInfo::Source::Rendered;
        m_journal->append(
            {journal_codec::encodeReference(m_journalledReference ? info : std::nullopt),
             {},
             rendered ? m_journalledReference : nullptr});
    });
}

void Autosave::discard() {
    m_journal->discard();
}

// A restore in progress: the entries and where it is.
struct Autosave::Restore {
    QString folder;
    Document* document = nullptr;
    std::vector<JournalEntry> entries;
    std::size_t next = 0;
    int restored = 0;
    bool complete = true;
    std::function<void(int, bool, const QString&)> done;
};

void Autosave::restore(
    const QString& folder, Document* document,
    std::function<void(int restored, bool complete, const QString& error)> done) {
    auto r = std::make_shared<Restore>();
    r->folder = folder;
    r->document = document;
    r->done = std::move(done);
    m_restoring = true;
    // 1. Read the journal (its renders and masks are EXR files) on a worker.
    struct Read {
        std::vector<JournalEntry> entries;
        bool complete = true;
    };
    m_tasks.run<Read>(
        QStringLiteral("read"),
        [folder](const TaskRunner::CancelFlag&) {
            Read read;
            read.entries = Journal::read(folder, &read.complete);
            return read;
        },
        [this, r](Read read) {
            r->entries = std::move(read.entries);
            r->complete = read.complete;
            step(r);
        },
        [this, r](const QString& message) { finish(r, message); });
}

void Autosave::finish(const std::shared_ptr<Restore>& r, const QString& error) {
    m_restoring = false;
    if (r->done) r->done(r->restored, r->complete, error);
}

void Autosave::step(const std::shared_ptr<Restore>& r) {
    // 2. The entries one after the other: each starts when the one before is in place.
    while (r->next < r->entries.size()) {
        const JournalEntry& entry = r->entries[r->next++];
        const QString op = entry.op.value(QStringLiteral("op")).toString();
        try {
            if (op == QStringLiteral("open")) {
                // Open the document without rendering (the journal brings the renders), and go
                // on once it is open (or could not be).
                const QString path = entry.op.value(QStringLiteral("path")).toString();
                if (!QFileInfo::exists(path)) continue;
                auto connections = std::make_shared<std::vector<QMetaObject::Connection>>();
                auto resume = [this, r, path, connections] {
                    for (const auto& c : *connections) disconnect(c);
                    recordOpen(path);
                    ++r->restored;
                    step(r);
                };
                connections->push_back(connect(r->document, &Document::opened, this, resume));
                connections->push_back(connect(r->document, &Document::failed, this, resume));
                r->document->open(path, false);
                return;
            }
            if (op == QStringLiteral("look")) {
                auto array = [&](const char* key) {
                    const QJsonArray a = entry.op.value(QLatin1String(key)).toArray();
                    return std::array<double, 3>{a.at(0).toDouble(), a.at(1).toDouble(),
                                                 a.at(2).toDouble()};
                };
                // A refused value throws from push() before the stack owns the command.
                auto command = std::make_unique<LookCommand>(
                    r->document, m_session,
                    entry.op.value(QStringLiteral("item")).toString().toStdString(),
                    entry.op.value(QStringLiteral("property")).toString().toStdString(),
                    array("before"), array("after"), false);
                m_session->undoStack()->push(command.get());
                command.release();
            } else if (op == QStringLiteral("settings")) {
                r->document->setSettings(
                    journal_codec::decodeSettings(entry.op, r->document->settings()));
            } else if (op == QStringLiteral("reference")) {
                // A file's reference is read again (and checked) in the background.
                const std::optional<ReferenceInfo> info =
                    journal_codec::decodeReference(entry.op, r->document->look());
                if (info)
                    r->document->restoreReference(*info, entry.frame, false);
                else
                    r->document->clearReference();
            } else if (op == QStringLiteral("undo")) {
                m_session->undoStack()->undo();
            } else if (op == QStringLiteral("redo")) {
                m_session->undoStack()->redo();
            } else if (op == QStringLiteral("input") && !entry.frame) {
                continue;  // superseded by a later render
            } else {
                // Filters run on a worker: go on when the entry is applied.
                m_session->replay(entry, [this, r](const QString& error) {
                    if (!error.isEmpty()) {
                        finish(r, error);
                        return;
                    }
                    ++r->restored;
                    // On the next turn of the event loop (done may come at once).
                    QMetaObject::invokeMethod(
                        this, [this, r] { step(r); }, Qt::QueuedConnection);
                });
                return;
            }
        } catch (const Error& e) {
            finish(r, QString::fromStdString(e.what()));
            return;
        }
        ++r->restored;
        // One entry per turn of the event loop: the studio keeps drawing.
        QMetaObject::invokeMethod(
            this, [this, r] { step(r); }, Qt::QueuedConnection);
        return;
    }
    // 3. Done: the old folder goes once this studio's journal holds everything.
    if (m_session->input()) r->document->setFinishedFrame(m_session->input());
    m_journal->afterWrites([this, r] {
        QDir(r->folder).removeRecursively();
        finish(r, QString());
    });
}

}  // namespace glint::studio
