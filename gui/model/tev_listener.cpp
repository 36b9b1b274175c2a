#include "model/tev_listener.h"

#include <QHostAddress>
#include <QTcpServer>
#include <QTcpSocket>

#include <cstdio>
#include <utility>

#include "glint/image/error.h"
#include "model/document.h"

namespace glint::studio {

TevListener::TevListener(Document* document, QObject* parent)
    : QObject(parent), m_document(document), m_server(new QTcpServer(this)) {
    connect(m_server, &QTcpServer::newConnection, this, &TevListener::accept);
    // A pass arrives as many packets (pbrt-v4: one a channel and tile): they make one frame.
    m_flush.setSingleShot(true);
    m_flush.setInterval(50);
    connect(&m_flush, &QTimer::timeout, this, &TevListener::show);
}

TevListener::~TevListener() = default;

QString TevListener::documentPath(const QString& name) {
    return QStringLiteral("tev:") + name;
}

bool TevListener::isReceived(const QString& path) {
    return path.startsWith(QStringLiteral("tev:"));
}

bool TevListener::listen(quint16 port, bool anyInterface) {
    const QHostAddress host = anyInterface ? QHostAddress::Any : QHostAddress::LocalHost;
    if (m_server->listen(host, port)) {
        log(tr("listening for tev clients on %1:%2")
                .arg(host.toString())
                .arg(m_server->serverPort()));
        return true;
    }
    log(tr("cannot listen on port %1: %2").arg(port).arg(m_server->errorString()));
    return false;
}

quint16 TevListener::port() const {
    return m_server->isListening() ? m_server->serverPort() : 0;
}

void TevListener::log(const QString& line) {
    std::fprintf(stderr, "glint-studio: tev: %s\n", qPrintable(line));
    emit logLine(line);
}

void TevListener::accept() {
    while (QTcpSocket* socket = m_server->nextPendingConnection()) {
        m_streams.insert(socket, std::make_shared<tev::PacketStream>());
        const QString peer = socket->peerAddress().toString();
        log(tr("a client connected from %1").arg(peer));
        connect(socket, &QTcpSocket::readyRead, this, [this, socket] { read(socket); });
        connect(socket, &QTcpSocket::disconnected, this, [this, socket] {
            m_streams.remove(socket);
            socket->deleteLater();
        });
    }
}

void TevListener::read(QTcpSocket* socket) {
    const auto found = m_streams.find(socket);
    if (found == m_streams.end()) return;
    const std::shared_ptr<tev::PacketStream> stream = *found;
    const QByteArray bytes = socket->readAll();
    stream->append(
        {reinterpret_cast<const unsigned char*>(bytes.constData()), std::size_t(bytes.size())});
    try {
        while (auto packet = stream->next()) apply(*packet);
    } catch (const Error& e) {
        // A broken length field: nothing after it can be found, so the client is dropped.
        log(tr("dropped the client: %1").arg(QString::fromStdString(oneLine(e.what()))));
        m_streams.remove(socket);
        socket->abort();
        socket->deleteLater();
    }
}

void TevListener::apply(const std::vector<unsigned char>& bytes) {
    try {
        const tev::Packet packet = tev::decode(bytes);
        const tev::Change change = m_images.apply(packet);
        if (change.kind == tev::Change::None) {
            log(tr("ignored %1 (the studio shows only images sent as pixels)")
                    .arg(QString::fromLatin1(tev::packetName(packet))));
            return;
        }
        m_changed.insert(QString::fromStdString(change.name));
        if (!m_flush.isActive()) m_flush.start();
    } catch (const Error& e) {
        log(tr("dropped a packet: %1").arg(QString::fromStdString(oneLine(e.what()))));
    }
}

void TevListener::show() {
    for (const QString& name : std::exchange(m_changed, {})) {
        const std::string key = name.toStdString();
        if (!m_images.has(key)) continue;
        auto frame = std::make_shared<const FrameBuffers>(m_images.frame(key));
        const bool complete = m_images.complete(key);
        // The first frame of an image opens it as the document; later ones replace its frame.
        if (m_document->path() == documentPath(name) && m_document->kind() == Document::Kind::Exr) {
            m_document->setFinishedFrame(frame);
        } else {
            Document::Loaded loaded;
            loaded.kind = Document::Kind::Exr;
            loaded.frame = frame;
            m_document->adopt(documentPath(name), std::move(loaded), false);
        }
        if (complete) m_images.forget(key);
        emit imageShown(name, complete);
    }
}

}  // namespace glint::studio
