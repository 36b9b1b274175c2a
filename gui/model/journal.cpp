#include "model/journal.h"

#include <QCoreApplication>
#include <QDir>
#include <QFile>
#include <QJsonArray>
#include <QJsonDocument>
#include <QRegularExpression>
#include <QThread>

#include <algorithm>
#include <filesystem>

#include "glint/image/error.h"
#include "glint/image/io.h"

namespace glint::studio {

namespace {

const QString kLines = QStringLiteral("journal.jsonl");

std::filesystem::path pathOf(const QString& folder, const QString& name) {
    return std::filesystem::path(QDir(folder).filePath(name).toStdString());
}

}  // namespace

Journal::Journal(const QString& folder, QObject* parent) : QObject(parent), m_folder(folder) {
    QDir(folder).removeRecursively();
    QDir().mkpath(folder);
}

// The runner's destructor waits for the writes still running.
Journal::~Journal() = default;

void Journal::append(const JournalEntry& entry) {
    if (m_paused) return;
    QJsonObject op = entry.op;
    // Side files first get their names; they are written in the background.
    QJsonArray images;
    for (const Image& image : entry.images) {
        const QString name = QStringLiteral("image-%1.exr").arg(m_next++, 6, 10, QLatin1Char('0'));
        images.append(name);
        auto copy = std::make_shared<const Image>(image);
        const std::filesystem::path file = pathOf(m_folder, name);
        ++m_pendingWrites;
        m_writes.run<bool>(
            name,
            [copy, file](const TaskRunner::CancelFlag&) {
                writeImage(*copy, file);
                return true;
            },
            [this](bool) { written(); }, [this](const QString&) { written(); });
    }
    if (!images.isEmpty()) op.insert(QStringLiteral("images"), images);
    if (op.value(QStringLiteral("op")).toString() == QStringLiteral("open"))
        m_previousPixels.clear();
    if (entry.frame) {
        const QString name = QStringLiteral("render-%1.exr").arg(m_next++, 6, 10, QLatin1Char('0'));
        op.insert(QStringLiteral("render"), name);
        FramePtr frame = entry.frame;
        const std::filesystem::path file = pathOf(m_folder, name);
        // Only the latest render matters to the final state: an older "input" render goes, and
        // so does the older "pixels" of the image a tev client keeps updating (a new "open"
        // starts another image, whose first pixels supersede nothing).
        const QString kind = op.value(QStringLiteral("op")).toString();
        QString superseded;
        if (kind == QStringLiteral("input")) {
            superseded = m_previousInput;
            m_previousInput = name;
        } else if (kind == QStringLiteral("pixels")) {
            superseded = m_previousPixels;
            m_previousPixels = name;
        }
        const QString folder = m_folder;
        ++m_pendingWrites;
        m_writes.run<bool>(
            name,
            [frame, file, superseded, folder](const TaskRunner::CancelFlag&) {
                writeExr(*frame, file, {.compression = ExrCompression::Zip});
                if (!superseded.isEmpty()) QFile::remove(QDir(folder).filePath(superseded));
                return true;
            },
            [this](bool) { written(); }, [this](const QString&) { written(); });
    }
    QFile file(QDir(m_folder).filePath(kLines));
    if (file.open(QIODevice::Append | QIODevice::WriteOnly)) {
        file.write(QJsonDocument(op).toJson(QJsonDocument::Compact));
        file.write("\n");
        file.flush();
    }
}

void Journal::flush() {
    // The writes report back through queued calls: run them until none is pending.
    while (m_pendingWrites > 0) {
        QCoreApplication::processEvents(QEventLoop::AllEvents, 10);
        QThread::msleep(1);
    }
}

void Journal::afterWrites(std::function<void()> fn) {
    if (m_pendingWrites == 0)
        fn();
    else
        m_afterWrites.push_back(std::move(fn));
}

void Journal::written() {
    if (--m_pendingWrites > 0) return;
    std::vector<std::function<void()>> waiting;
    waiting.swap(m_afterWrites);
    for (auto& fn : waiting) fn();
}

void Journal::discard() {
    flush();
    QDir(m_folder).removeRecursively();
}

bool Journal::adopt(const QString& folder, int entries) {
    flush();
    QFile in(QDir(folder).filePath(kLines));
    if (!in.open(QIODevice::ReadOnly)) return false;
    const QList<QByteArray> lines = in.readAll().split('\n');
    in.close();
    // The entries read, and where their side files stand: the render an "input" or "pixels"
    // entry supersedes next, and the next free number.
    QByteArray kept;
    QString previousInput, previousPixels;
    int count = 0;
    for (const QByteArray& line : lines) {
        if (count == entries) break;
        if (line.trimmed().isEmpty()) continue;
        kept += line + '\n';
        ++count;
        const QJsonObject op = QJsonDocument::fromJson(line).object();
        const QString kind = op.value(QStringLiteral("op")).toString();
        const QString render = op.value(QStringLiteral("render")).toString();
        const bool onDisk = !render.isEmpty() && QFile::exists(QDir(folder).filePath(render));
        if (kind == QStringLiteral("open")) previousPixels.clear();
        if (kind == QStringLiteral("input") && onDisk) previousInput = render;
        if (kind == QStringLiteral("pixels") && onDisk) previousPixels = render;
    }
    if (count != entries) return false;
    int next = 0;
    static const QRegularExpression numbered(QStringLiteral("^(image|render)-(\\d+)\\.exr$"));
    for (const QString& name : QDir(folder).entryList(QDir::Files)) {
        const QRegularExpressionMatch m = numbered.match(name);
        if (m.hasMatch()) next = std::max(next, m.captured(2).toInt() + 1);
    }
    // The lines kept, written to a temporary name and renamed over the journal.
    const QString temporary = QDir(folder).filePath(kLines + QStringLiteral(".adopting"));
    QFile out(temporary);
    if (!out.open(QIODevice::WriteOnly | QIODevice::Truncate) || out.write(kept) != kept.size())
        return false;
    out.close();
    std::error_code error;
    std::filesystem::rename(pathOf(folder, kLines + QStringLiteral(".adopting")),
                            pathOf(folder, kLines), error);
    if (error) return false;
    // This journal's own folder gives way (the restore replaces everything it recorded).
    QDir(m_folder).removeRecursively();
    if (!QDir().rename(folder, m_folder)) {
        QDir().mkpath(m_folder);
        return false;
    }
    m_next = next;
    m_previousInput = previousInput;
    m_previousPixels = previousPixels;
    return true;
}

std::vector<JournalEntry> Journal::read(const QString& folder, bool* complete) {
    std::vector<JournalEntry> entries;
    if (complete) *complete = true;
    QFile file(QDir(folder).filePath(kLines));
    if (!file.open(QIODevice::ReadOnly)) {
        if (complete) *complete = false;
        return entries;
    }
    const QList<QByteArray> lines = file.readAll().split('\n');
    // Of the "input" renders, and of the "pixels" ones, only the latest on disk is read (an
    // older one is removed once the next is written, so a crash during that write leaves the
    // older); the others' entries come without their render.
    int lastInput = -1, lastPixels = -1;
    for (int i = 0; i < lines.size(); ++i) {
        const QJsonObject op = QJsonDocument::fromJson(lines[i]).object();
        if (!QFile::exists(QDir(folder).filePath(op.value(QStringLiteral("render")).toString())))
            continue;
        const QString kind = op.value(QStringLiteral("op")).toString();
        if (kind == QStringLiteral("input")) lastInput = i;
        if (kind == QStringLiteral("pixels")) lastPixels = i;
    }
    for (int i = 0; i < lines.size(); ++i) {
        if (lines[i].trimmed().isEmpty()) continue;
        QJsonParseError error{};
        const QJsonDocument doc = QJsonDocument::fromJson(lines[i], &error);
        if (error.error != QJsonParseError::NoError || !doc.isObject()) {
            if (complete) *complete = false;
            break;
        }
        JournalEntry entry;
        entry.op = doc.object();
        try {
            for (const QJsonValue& name : entry.op.value(QStringLiteral("images")).toArray())
                entry.images.push_back(readImage(pathOf(folder, name.toString()), false));
            const QString render = entry.op.value(QStringLiteral("render")).toString();
            const QString kind = entry.op.value(QStringLiteral("op")).toString();
            const bool latestOnly =
                kind == QStringLiteral("input") || kind == QStringLiteral("pixels");
            const int latest = kind == QStringLiteral("input") ? lastInput : lastPixels;
            if (!render.isEmpty() && (!latestOnly || i == latest))
                entry.frame = std::make_shared<const FrameBuffers>(readExr(pathOf(folder, render)));
        } catch (const Error&) {
            if (complete) *complete = false;
            break;
        }
        entries.push_back(std::move(entry));
    }
    return entries;
}

}  // namespace glint::studio
