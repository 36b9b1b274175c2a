#include "model/first_denoise.h"

#include <QUndoStack>

#include <memory>
#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "model/document.h"
#include "model/learned_member.h"
#include "model/session_adapter.h"

namespace glint::studio {

FirstDenoise::FirstDenoise(Document* document, SessionAdapter* session,
                           std::function<bool()> allowed, QObject* parent)
    : QObject(parent), m_document(document), m_session(session), m_allowed(std::move(allowed)) {
    // Armed by opening a file; the first session started on its render disarms it, with or
    // without a layer (a loaded session or a restored journal brings its own layers).
    connect(m_document, &Document::opened, this, [this] { m_armed = true; });
    connect(m_session, &SessionAdapter::sessionReset, this, &FirstDenoise::onSessionReset);
    // Whether the learned filter runs here is known by the time the first render lands.
    probeLearnedFilter();
}

std::string FirstDenoise::filterFor(const FrameBuffers& frame) {
    if (frame.has(Layer::Albedo) && frame.has(Layer::Normal) && learnedFilterAvailable())
        return kLearnedFilter;
    const denoise::Filter& filter = denoise::findFilter(kClassicalFilter);
    // A frame without the features the filter needs stays raw (no error for what nobody asked).
    std::vector<Layer> needed = filter.requiredLayers(denoise::resolveParams(filter, {}));
    needed.insert(needed.end(), {Layer::Albedo, Layer::Normal, Layer::Depth});  // its guides
    for (Layer layer : needed)
        if (!frame.has(layer)) return {};
    return kClassicalFilter;
}

void FirstDenoise::onSessionReset() {
    if (!m_armed || !m_session->hasSession()) return;
    m_armed = false;
    if (m_session->session().layerCount() != 0 || (m_allowed && !m_allowed())) return;
    if (m_session->input() != m_document->finishedFrame()) return;  // not this file's render
    const std::string name = filterFor(*m_session->input());
    if (name.empty()) return;
    const denoise::Session& s = m_session->session();
    QUndoStack* stack = m_session->undoStack();
    if (stack->isClean()) {
        // The automatic layer is part of what was opened: its step leaves the file unmodified
        // (no "*" right after opening). Added on a worker, it is the first step pushed.
        auto once = std::make_shared<QMetaObject::Connection>();
        *once = connect(stack, &QUndoStack::indexChanged, this, [this, stack, once] {
            disconnect(*once);
            if (stack->count() == 1 && m_session->session().layerCount() == 1) stack->setClean();
        });
    }
    m_session->addLayer(name, denoise::resolveParams(denoise::findFilter(name), {}),
                        Image(s.width(), s.height(), 1, 1.0f));
}

}  // namespace glint::studio
