#include "model/tev_sender.h"

#include <QFileInfo>

#include "glint/image/tev_client.h"
#include "model/document.h"

namespace glint::studio {

TevSender::TevSender(Document* document, QObject* parent) : QObject(parent), m_document(document) {
    connect(document, &Document::frameChanged, this, &TevSender::frameChanged);
    // Another file: another image in tev.
    connect(document, &Document::opened, this, [this] { m_display.reset(); });
}

TevSender::~TevSender() = default;

void TevSender::setAddress(const QString& address) {
    if (!address.isEmpty()) tev::parseAddress(address.toStdString(), "tev display");
    m_display.reset();
    m_address = address;
}

void TevSender::frameChanged() {
    const FramePtr frame = m_document->frame();
    if (m_address.isEmpty() || !frame || m_document->kind() != Document::Kind::Scene) return;
    if (!m_display) {
        tev::DisplayOptions options;
        options.address = tev::parseAddress(m_address.toStdString(), "tev display");
        options.name = QFileInfo(m_document->path()).fileName().toStdString();
        // The warning comes from the display's thread (which ~TevSender joins): it reaches the
        // log through a queued call.
        options.warn = [this](const std::string& line) {
            const QString text = QString::fromStdString(line);
            QMetaObject::invokeMethod(
                this, [this, text] { emit logLine(text); }, Qt::QueuedConnection);
        };
        m_display = std::make_unique<tev::Display>(std::move(options));
    }
    m_display->show(frame);
}

}  // namespace glint::studio
