#include "model/progressive_denoise.h"

#include "model/document.h"
#include "model/session_adapter.h"

namespace glint::studio {

ProgressiveDenoise::ProgressiveDenoise(Document* document, SessionAdapter* session,
                                       std::function<bool()> allowed, QObject* parent)
    : QObject(parent), m_document(document), m_session(session), m_allowed(std::move(allowed)) {
    connect(m_document, &Document::frameChanged, this, [this](bool final) {
        if (!final) onPass();
    });
    // The latest pass wins: one that arrived during a re-application is taken as soon as it ends
    // (queued: after the session installed it), not left for the next pass.
    connect(
        m_session, &SessionAdapter::busyChanged, this,
        [this](bool busy) {
            if (!busy && m_document->rendering()) onPass();
        },
        Qt::QueuedConnection);
}

void ProgressiveDenoise::onPass() {
    if (m_allowed && !m_allowed()) return;
    // Only under layers to keep (without them the canvas shows the passes raw already), for a
    // whole-frame render, and one re-application at a time (the throttle).
    if (!m_session->hasSession() || m_session->session().layerCount() == 0) return;
    if (m_session->busy() || m_session->locked() || m_document->renderingRegion()) return;
    const FramePtr pass = m_document->frame();
    const FramePtr shown = m_session->input();
    if (!pass || !shown || pass == shown) return;
    if (pass->width() != shown->width() || pass->height() != shown->height()) return;
    // Better than what is on screen: at least as many samples per pixel.
    if (pass->metadata().spp < shown->metadata().spp) return;
    m_session->setInput(pass, false);
    ++m_previews;
}

}  // namespace glint::studio
