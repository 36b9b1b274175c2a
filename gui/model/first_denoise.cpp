#include "model/first_denoise.h"

#include <QUndoStack>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "model/document.h"
#include "model/learned_member.h"
#include "model/session_adapter.h"

namespace glint::studio {

namespace {

// Whether `frame` has every layer the filter `name` needs at its defaults (its guides included).
bool runsOn(const std::string& name, const FrameBuffers& frame) {
    const denoise::Filter& filter = denoise::findFilter(name);
    const std::vector<Layer> needed = filter.requiredLayers(denoise::resolveParams(filter, {}));
    return std::all_of(needed.begin(), needed.end(), [&](Layer l) { return frame.has(l); });
}

// The centred window of at most side² pixels the candidates are measured over.
Rect measuredWindow(const FrameBuffers& frame, int side) {
    const int w = std::min(side, frame.width()), h = std::min(side, frame.height());
    const int x0 = (frame.width() - w) / 2, y0 = (frame.height() - h) / 2;
    return Rect{x0, x0 + w, y0, y0 + h};
}

}  // namespace

const std::vector<std::string>& FirstDenoise::classicalCandidates() {
    // The default filters of the bank that keep edges; the Gaussian and the plain bilateral
    // blur what they do not see (they lose on every scene of docs/lab/first-denoise.md).
    static const std::vector<std::string> names{"cross-bilateral", "nlmeans", "guided"};
    return names;
}

std::vector<std::string> FirstDenoise::candidatesFor(const FrameBuffers& frame) {
    std::vector<std::string> names;
    if (frame.has(Layer::Albedo) && frame.has(Layer::Normal) && learnedFilterAvailable())
        names.emplace_back(kLearnedFilter);
    // A frame without the render's guides (a colour-only EXR) stays raw, as it always did: the
    // candidates are measured on renders with features.
    if (!frame.has(Layer::Albedo) || !frame.has(Layer::Normal) || !frame.has(Layer::Depth))
        return names;
    for (const std::string& name : classicalCandidates())
        if (runsOn(name, frame)) names.push_back(name);
    return names;
}

FirstDenoiseChoice FirstDenoise::choose(const FrameBuffers& frame) {
    std::vector<std::string> candidates = candidatesFor(frame);
    // The learned filter beats every classical one at 4, 16 and 64 spp on every scene the lab
    // measured (docs/lab/first-denoise.md): that measurement ships as the default. SURE on the
    // frame cannot overrule it: on a 16-spp render its means are within their own noise (some
    // negative). Among the classical filters, whose ranking changes from scene to scene, the
    // frame's own measurement chooses.
    // Its weights for noisy features (the default) blur texture detail the albedo holds: with
    // features clean enough, its weights for clean ones (docs/lab/first-denoise.md, "Detail").
    if (!candidates.empty() && candidates.front() == kLearnedFilter) {
        FirstDenoiseChoice learned{kLearnedFilter, {}, {}};
        if (featuresAreClean(frame)) {
            const denoise::Filter& unet = denoise::findFilter(kLearnedFilter);
            learned.params["aux"] =
                denoise::parseParamValue(*denoise::findParam(unet.params(), "aux"), "clean");
        }
        return learned;
    }
    return choose(frame, candidates);
}

bool FirstDenoise::featuresAreClean(const FrameBuffers& frame) {
    // The mean of a variance layer over its finite values (every pixel and channel).
    auto meanOf = [](const Image& image) {
        double sum = 0.0;
        std::size_t count = 0;
        for (float v : image.data())
            if (std::isfinite(v)) {
                sum += double(v);
                ++count;
            }
        return count == 0 ? std::numeric_limits<double>::infinity() : sum / double(count);
    };
    if (!frame.has(Layer::AlbedoVariance) || !frame.has(Layer::NormalVariance)) return false;
    return meanOf(frame.layer(Layer::AlbedoVariance)) <= kCleanFeatureVariance &&
           meanOf(frame.layer(Layer::NormalVariance)) <= kCleanFeatureVariance;
}

FirstDenoiseChoice FirstDenoise::choose(const FrameBuffers& frame,
                                        const std::vector<std::string>& candidates) {
    FirstDenoiseChoice choice;
    if (candidates.empty()) return choice;
    choice.filter = candidates.front();
    if (candidates.size() == 1) return choice;
    // 1. Each candidate's defaults over the window: a bank of the candidates.
    const Rect window = measuredWindow(frame, kMeasuredSide);
    std::vector<denoise::BankMember> members;
    std::vector<Image> results;
    for (const std::string& name : candidates) {
        const denoise::Filter& f = denoise::findFilter(name);
        const denoise::ParamValues params = denoise::resolveParams(f, {});
        members.push_back({name, params, true});
        denoise::FilterOptions only;
        only.region = window;
        results.push_back(denoise::applyFilter(f, frame, params, only));
    }
    const denoise::FilterBank bank(std::move(members), std::move(results), window, frame.width(),
                                   frame.height(), denoise::hashFrame(frame));
    // 2. Auto's estimate of each one's error (no reference): SURE, the halves or the image-only
    // estimate, as the frame allows. A frame that cannot be estimated keeps the first.
    denoise::AutoOptions options;
    options.allowStacking = false;
    denoise::AutoResult result;
    try {
        result = denoise::autoComposite(bank, frame, options);
    } catch (const Error&) {
        return choice;
    }
    // 3. The smallest estimate (the first of equals: the candidates' order is the preference).
    std::size_t best = 0;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        choice.estimates.push_back({candidates[i], result.estimatedMse[i]});
        if (result.estimatedMse[i] < result.estimatedMse[best]) best = i;
    }
    choice.filter = candidates[best];
    return choice;
}

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

void FirstDenoise::onSessionReset() {
    if (!m_armed || !m_session->hasSession()) return;
    m_armed = false;
    if (m_session->session().layerCount() != 0 || (m_allowed && !m_allowed())) return;
    if (m_session->input() != m_document->finishedFrame()) return;  // not this file's render
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
    // Measured and filtered on the session's worker (the filters' input: prefiltered features
    // when the session says so), weight 1 everywhere.
    m_session->addChosenLayer(
        [](const FrameBuffers& in) {
            FirstDenoiseChoice choice = choose(in);
            return std::make_pair(std::move(choice.filter), std::move(choice.params));
        },
        Image(s.width(), s.height(), 1, 1.0f));
}

}  // namespace glint::studio
