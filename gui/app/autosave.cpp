#include "app/autosave.h"

#include <QCoreApplication>
#include <QDateTime>
#include <QDir>
#include <QFile>
#include <QFileInfo>
#include <QStandardPaths>
#include <memory>

#include <signal.h>
#include <unistd.h>

#include "model/journal_codec.h"
#include "model/tev_listener.h"

namespace glint::studio {

namespace {

bool processAlive(qint64 pid) {
    return pid > 0 && (::kill(pid_t(pid), 0) == 0 || errno == EPERM);
}

}  // namespace

Autosave::Autosave(const QString& base, SessionAdapter* session, QObject* parent)
    : QObject(parent) {
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

void Autosave::recordOpen(const Document& document) {
    const QString path = document.path();
    const bool received = TevListener::isReceived(path);
    m_journalledReceived = received ? document.finishedFrame() : nullptr;
    JournalEntry entry;
    entry.op = {{QStringLiteral("op"), QStringLiteral("open")},
                {QStringLiteral("path"), received ? path : QFileInfo(path).absoluteFilePath()}};
    entry.frame = m_journalledReceived;
    m_journal->append(entry);
}

void Autosave::watch(Document* document) {
    connect(document, &Document::frameChanged, this, [this, document](bool final) {
        // A tev client's update of a received image: its latest pixels (op "pixels").
        const FramePtr frame = document->finishedFrame();
        if (!final || !frame || !TevListener::isReceived(document->path()) ||
            frame == m_journalledReceived)
            return;
        m_journalledReceived = frame;
        m_journal->append({{{QStringLiteral("op"), QStringLiteral("pixels")}}, {}, frame});
    });
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

void Autosave::restore(
    const QString& folder,
    std::function<void(std::shared_ptr<Recovered> recovered, const QString& error)> done) {
    m_restoring = true;
    // Reading the journal, its renders and masks, opening the file and replaying every edit:
    // all on a worker. The UI thread gets the finished state.
    m_tasks.run<std::shared_ptr<Recovered>>(
        QStringLiteral("restore"),
        [folder](const TaskRunner::CancelFlag& cancel) {
            return std::make_shared<Recovered>(
                recover(folder, [cancel](double) { return !cancel->load(); }));
        },
        [this, done](std::shared_ptr<Recovered> recovered) {
            m_restoring = false;
            done(std::move(recovered), QString());
        },
        [this, done](const QString& error) {
            m_restoring = false;
            done(nullptr, error);
        });
}

void Autosave::finishRestore(const QString& folder) {
    m_journal->afterWrites([folder] { QDir(folder).removeRecursively(); });
}

QString Autosave::setAside(const QString& folder) {
    const QFileInfo info(folder);
    const QString kept = info.dir().filePath(
        info.fileName() + QStringLiteral(".kept-") +
        QDateTime::currentDateTime().toString(QStringLiteral("yyyyMMdd-HHmmss")));
    return QDir().rename(folder, kept) ? kept : QString();
}

}  // namespace glint::studio
