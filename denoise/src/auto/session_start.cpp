// Starting a painting session from the auto composite (startFromAuto, auto.h; docs/auto.md,
// "Starting a session from auto").
#include <algorithm>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"

namespace glint::denoise {

std::size_t startFromAuto(Session& session, const FilterBank& bank, const AutoResult& result) {
    const Rect whole{0, session.width(), 0, session.height()};
    if (bank.region() != whole || bank.frameWidth() != session.width() ||
        bank.frameHeight() != session.height())
        throw Error(ErrorKind::InvalidArgument, "an automatic start needs a bank over the whole " +
                                                    std::to_string(session.width()) + "x" +
                                                    std::to_string(session.height()) + " frame");
    if (bank.inputHash() != hashFrame(session.input()))
        throw Error(ErrorKind::InvalidArgument,
                    "the bank was computed from another image than the session's input");
    if (result.composite.width() != whole.width() || result.composite.height() != whole.height() ||
        result.composite.channels() != 3)
        throw Error(ErrorKind::InvalidArgument, "the auto result is not of this bank");
    for (const AutoLayer& l : result.layers)
        if (l.member < 0 || std::size_t(l.member) >= bank.size() ||
            l.weights.width() != whole.width() || l.weights.height() != whole.height())
            throw Error(ErrorKind::InvalidArgument, "the auto result is not of this bank");
    // Sequential blending: with S_k the sum of the first k layers' weights, layer k shows with
    // a_k = w_k / S_k, so that composite_k = Σ_{j≤k} w_j f_j / S_k and the last one Σ w f.
    const std::size_t pixels = std::size_t(whole.width()) * std::size_t(whole.height());
    std::vector<double> cumulative(pixels, 0.0);
    std::size_t edits = 0;
    try {
        for (const AutoLayer& l : result.layers) {
            Image a(whole.width(), whole.height(), 1);
            for (std::size_t p = 0; p < pixels; ++p) {
                const double w = l.weights.data()[p];
                cumulative[p] += w;
                a.data()[p] = cumulative[p] > 0.0 ? float(std::min(1.0, w / cumulative[p])) : 0.0f;
            }
            const BankMember& member = bank.members()[std::size_t(l.member)];
            // A bank streamed without its results: the session runs the member.
            const std::size_t index = bank.results().empty()
                                          ? session.addLayer(member.filter, member.params)
                                          : session.addLayer(member.filter, member.params,
                                                             bank.result(std::size_t(l.member)));
            session.setWeights(index, a);
            edits += 2;
        }
        // Auto's correction: what takes the blend to auto's result — the stacking's correction, and
        // the float rounding by which the session's blend differs from auto's — so that the session
        // is auto's result bit for bit.
        const auto& now = session.composite().data();
        const auto& target = result.composite.data();
        if (!std::equal(now.begin(), now.end(), target.begin(), target.end())) {
            const std::size_t index = session.addCorrection(result.composite);
            session.setWeights(index, Image(whole.width(), whole.height(), 1, 1.0f));
            edits += 2;
        }
    } catch (...) {
        // A layer that could not be added (a filter that stopped, a non-finite result): the
        // edits made are taken back.
        for (std::size_t i = 0; i < edits; ++i) session.undo();
        throw;
    }
    return edits;
}

}  // namespace glint::denoise
