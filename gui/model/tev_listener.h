// The studio as a tev display server (docs/studio.md, "Receiving images"): it listens on a TCP
// port (loopback only unless asked) so that pbrt-v4's --display-server, glint-render --display
// or any tev client can send images. CreateImage, UpdateImage and CloseImage build an image
// (glint/image/tev_images.h) that becomes the document as it grows, to be denoised, painted and
// compared like an opened EXR. A malformed packet is dropped with one line in the log (stderr
// and logLine); a stream that cannot be followed is disconnected. No widgets here.
#pragma once

#include <QHash>
#include <QObject>
#include <QSet>
#include <QString>
#include <QTimer>

#include <memory>

#include "glint/image/tev_images.h"
#include "glint/image/tev_protocol.h"

class QTcpServer;
class QTcpSocket;

namespace glint::studio {

class Document;

class TevListener : public QObject {
    Q_OBJECT
  public:
    explicit TevListener(Document* document, QObject* parent = nullptr);
    ~TevListener() override;

    /// Listens on `port` (0: any free port) of 127.0.0.1, or of every interface when
    /// `anyInterface`. False (with a log line) when the port cannot be had.
    bool listen(quint16 port, bool anyInterface = false);
    /// The port listened on (0 when not listening).
    quint16 port() const;
    /// The document path of a received image ("tev:NAME").
    static QString documentPath(const QString& name);
    /// True when the document `path` is a received image (no file on disk: the autosave keeps
    /// its pixels).
    static bool isReceived(const QString& path);

  signals:
    /// One line for the log: a client connected or left, a packet dropped and why.
    void logLine(const QString& line);
    /// The image `name` was shown in the document (`complete`: it was closed by its client).
    void imageShown(const QString& name, bool complete);

  private:
    void accept();
    void read(QTcpSocket* socket);
    void apply(const std::vector<unsigned char>& bytes);
    void show();
    void log(const QString& line);

    Document* m_document;
    QTcpServer* m_server;
    QHash<QTcpSocket*, std::shared_ptr<tev::PacketStream>> m_streams;
    tev::ReceivedImages m_images;
    QSet<QString> m_changed;  // images to show at the next flush
    QTimer m_flush;           // coalesces the packets of one pass into one new frame
};

}  // namespace glint::studio
