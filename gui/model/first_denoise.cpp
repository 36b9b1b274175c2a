#include "model/first_denoise.h"

#include <vector>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "model/document.h"
#include "model/session_adapter.h"

namespace glint::studio {

FirstDenoise::FirstDenoise(Document* document, SessionAdapter* session,
                           std::function<bool()> allowed, QObject* parent)
    : QObject(parent), m_document(document), m_session(session), m_allowed(std::move(allowed)) {
    // Armed by opening a file; the first session started on its render disarms it, with or
    // without a layer (a loaded session or a restored journal brings its own layers).
    connect(m_document, &Document::opened, this, [this] { m_armed = true; });
    connect(m_session, &SessionAdapter::sessionReset, this, &FirstDenoise::onSessionReset);
}

void FirstDenoise::onSessionReset() {
    if (!m_armed || !m_session->hasSession()) return;
    m_armed = false;
    if (m_session->session().layerCount() != 0 || (m_allowed && !m_allowed())) return;
    if (m_session->input() != m_document->finishedFrame()) return;  // not this file's render
    const denoise::Filter& filter = denoise::findFilter(kFilter);
    const denoise::ParamValues params = denoise::resolveParams(filter, {});
    // An EXR without the features the filter needs stays raw (no error for what nobody asked).
    std::vector<Layer> needed = filter.requiredLayers(params);
    needed.insert(needed.end(), {Layer::Albedo, Layer::Normal, Layer::Depth});  // its guides
    for (Layer layer : needed)
        if (!m_session->input()->has(layer)) return;
    const denoise::Session& s = m_session->session();
    m_session->addLayer(kFilter, params, Image(s.width(), s.height(), 1, 1.0f));
}

}  // namespace glint::studio
