// The main window's tev parts: the listener that makes received images the document and the
// sender of render passes (docs/studio.md, "Receiving images" and "Sending renders to tev").
#include <QStatusBar>

#include "app/main_window.h"
#include "glint/image/error.h"
#include "model/tev_listener.h"
#include "model/tev_sender.h"

namespace glint::studio {

void MainWindow::connectTev() {
    m_tevSender = new TevSender(m_document, this);
    connect(m_tevSender, &TevSender::logLine, this,
            [this](const QString& line) { showStatus(tr("tev: %1").arg(line)); });
    try {
        m_tevSender->setAddress(m_options.tevDisplay);
    } catch (const Error& e) {
        showStatus(tr("tev: %1").arg(QString::fromStdString(oneLine(e.what()))));
    }
    if (m_options.tevListenPort < 0) return;
    m_tevListener = new TevListener(m_document, this);
    connect(m_tevListener, &TevListener::logLine, this,
            [this](const QString& line) { showStatus(tr("tev: %1").arg(line)); });
    m_tevListener->listen(quint16(m_options.tevListenPort), m_options.tevAnyInterface);
}

}  // namespace glint::studio
