#include "model/learned_member.h"

#include <exception>
#include <future>
#include <mutex>

#include <QCoreApplication>

#include "glint/denoise/filter.h"
#include "glint/denoise/registry.h"
#include "glint/image/frame_buffers.h"

namespace glint::studio {

namespace {

// Runs the learned filter on a tiny frame with the layers a render has, then with colour alone:
// each reads (and checks) the weights it needs. Returns the first error, or "".
std::string probe() {
    try {
        const denoise::Filter& filter = denoise::findFilter(kLearnedFilter);
        if (std::string why = filter.unavailable(denoise::resolveParams(filter, {})); !why.empty())
            return why;
        constexpr int kSide = 16;
        FrameBuffers frame(kSide, kSide);
        frame.set(Layer::Color, Image(kSide, kSide, 3, 0.5f));
        frame.set(Layer::Albedo, Image(kSide, kSide, 3, 0.5f));
        Image normal(kSide, kSide, 3, 0.0f);
        for (int y = 0; y < kSide; ++y)
            for (int x = 0; x < kSide; ++x) normal(x, y, 2) = 1.0f;
        frame.set(Layer::Normal, normal);
        denoise::FilterOptions options;
        options.threads = 1;
        (void)denoise::applyFilter(filter, frame, {}, options);
        FrameBuffers colourOnly(kSide, kSide);
        colourOnly.set(Layer::Color, frame.color());
        (void)denoise::applyFilter(filter, colourOnly, {}, options);
        return {};
    } catch (const std::exception& e) {
        return e.what();
    }
}

struct Probe {
    std::once_flag started;
    std::shared_future<std::string> answer;
};

Probe& theProbe() {
    static Probe p;
    return p;
}

}  // namespace

void probeLearnedFilter() {
    Probe& p = theProbe();
    std::call_once(p.started, [&p] {
        p.answer = std::async(std::launch::async, probe).share();
        // The probe's thread builds the filter's statics (oneDNN, the weights): the application
        // waits for it as it ends, before any static is destroyed under it (QTest's main too).
        if (QCoreApplication::instance())
            qAddPostRoutine([] {
                if (theProbe().answer.valid()) theProbe().answer.wait();
            });
    });
}

const std::string& learnedFilterUnavailable() {
    probeLearnedFilter();
    return theProbe().answer.get();
}

bool learnedFilterAvailable() {
    return learnedFilterUnavailable().empty();
}

std::vector<std::string> studioBankFilters() {
    std::vector<std::string> names;
    for (const denoise::Filter* f : denoise::defaultBankFilters()) {
        if (f->name() == kLearnedFilter) return {};
        names.emplace_back(f->name());
    }
    if (!learnedFilterAvailable()) return {};
    names.emplace_back(kLearnedFilter);
    return names;
}

}  // namespace glint::studio
