#include "app/autosave.h"

#include <QCoreApplication>
#include <QDir>
#include <QEventLoop>
#include <QFile>
#include <QFileInfo>
#include <QJsonArray>
#include <QStandardPaths>
#include <QTimer>
#include <memory>

#include <signal.h>
#include <unistd.h>

#include "glint/image/error.h"
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

void Autosave::discard() {
    m_journal->discard();
}

int Autosave::restore(const QString& folder, Document* document, bool* complete) {
    const std::vector<JournalEntry> entries = Journal::read(folder, complete);
    int restored = 0;
    for (const JournalEntry& entry : entries) {
        const QString op = entry.op.value(QStringLiteral("op")).toString();
        if (op == QStringLiteral("open")) {
            // Open the document without rendering: the journal brings the renders.
            const QString path = entry.op.value(QStringLiteral("path")).toString();
            if (!QFileInfo::exists(path)) continue;
            QEventLoop loop;
            auto a = connect(document, &Document::opened, &loop, &QEventLoop::quit);
            auto b = connect(document, &Document::failed, &loop, &QEventLoop::quit);
            document->open(path, false);
            loop.exec();
            disconnect(a);
            disconnect(b);
            recordOpen(path);
        } else if (op == QStringLiteral("look")) {
            auto array = [&](const char* key) {
                const QJsonArray a = entry.op.value(QLatin1String(key)).toArray();
                return std::array<double, 3>{a.at(0).toDouble(), a.at(1).toDouble(),
                                             a.at(2).toDouble()};
            };
            // A refused value throws from push() before the stack owns the command.
            auto command = std::make_unique<LookCommand>(
                document, m_session,
                entry.op.value(QStringLiteral("item")).toString().toStdString(),
                entry.op.value(QStringLiteral("property")).toString().toStdString(),
                array("before"), array("after"), false);
            m_session->undoStack()->push(command.get());
            command.release();
        } else if (op == QStringLiteral("undo")) {
            m_session->undoStack()->undo();
        } else if (op == QStringLiteral("redo")) {
            m_session->undoStack()->redo();
        } else if (op == QStringLiteral("input") && !entry.frame) {
            continue;  // superseded by a later render
        } else {
            m_session->replay(entry);
        }
        ++restored;
    }
    if (m_session->input()) document->setFinishedFrame(m_session->input());
    m_journal->flush();
    QDir(folder).removeRecursively();
    return restored;
}

}  // namespace glint::studio
