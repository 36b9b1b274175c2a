// The studio's renders shown in tev (docs/studio.md, "Sending renders to tev"): each pass of a
// scene's render goes to a running tev as the image named after the scene file, sent on the
// display's own thread (glint/image/tev_client.h). Off unless an address is set. No widgets.
#pragma once

#include <QObject>
#include <QString>

#include <memory>

namespace glint::tev {
class Display;
}

namespace glint::studio {

class Document;

class TevSender : public QObject {
    Q_OBJECT
  public:
    explicit TevSender(Document* document, QObject* parent = nullptr);
    ~TevSender() override;

    /// Sends to tev at "HOST:PORT" from the next pass on; empty turns it off. Throws
    /// glint::Error(InvalidArgument) for an address that is not HOST:PORT.
    void setAddress(const QString& address);
    QString address() const { return m_address; }

  signals:
    /// One line for the log: tev is not there or went away (once per address and document).
    void logLine(const QString& line);

  private:
    void frameChanged();

    Document* m_document;
    QString m_address;
    std::unique_ptr<tev::Display> m_display;
};

}  // namespace glint::studio
