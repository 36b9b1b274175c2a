// The stacking stage of the automatic selection (stacking.h; docs/auto.md, "Stacking"): the
// blends on the halves, the regressors, then the regression (stack_regression.cpp).
#include "stacking.h"

#include "blend.h"
#include "display_weights.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/progress.h"
#include "halves_estimator.h"
#include "options.h"

namespace glint::denoise::detail {

Stacked stack(const Image& composite, const std::vector<Image>& planes,
              const std::vector<int>& order, const FilterBank& bank, const FrameBuffers& frame,
              const HalvesEstimator& halves, const AutoSettings& settings, WorkContext& work) {
    const Rect& region = bank.region();
    const int width = region.width();
    const std::size_t n = planes.size();
    // The blend on each half: the composite's weights applied to the members' results there.
    Image blendA(width, region.height(), 3), blendB(width, region.height(), 3);
    std::vector<const Image*> resultsA(n, nullptr), resultsB(n, nullptr);
    for (std::size_t m = 0; m < n; ++m)
        if (!planes[m].empty()) resultsA[m] = &halves.onA(m), resultsB[m] = &halves.onB(m);
    work.parallelFor(0, region.height(), [&](int y) {
        std::vector<double> a(std::size_t(width) * 3), b(std::size_t(width) * 3);
        blendRow(planes, resultsA, y, a);
        blendRow(planes, resultsB, y, b);
        std::copy(a.begin(), a.end(), blendA.row(y));
        std::copy(b.begin(), b.end(), blendB.row(y));
    });
    // The members of largest total weight.
    std::vector<StackMember> stacked;
    for (int m : order) {
        if (stacked.size() == std::size_t(settings.stack)) break;
        const std::size_t i = std::size_t(m);
        stacked.push_back({&bank.result(i), &halves.onA(i), &halves.onB(i)});
    }
    // The features' regressors, from the whole frame's features around the composite and from
    // each half's around its blend.
    std::vector<Image> features[3];
    if (settings.stackAlbedo || settings.stackNormal) {
        // As the filters saw them: prefiltered when the bank was.
        const FrameBuffers prefiltered = settings.prefilter
                                             ? prefilterFeatures(frame, settings.prefilterParams)
                                             : FrameBuffers{};
        const FrameBuffers* sources[3] = {settings.prefilter ? &prefiltered : &frame,
                                          &halves.halfA(), &halves.halfB()};
        const Image* bases[3] = {&composite, &blendA, &blendB};
        for (int side = 0; side < 3; ++side) {
            const Image albedo =
                settings.stackAlbedo ? sources[side]->layer(Layer::Albedo).crop(region) : Image{};
            const Image normal =
                settings.stackNormal ? sources[side]->layer(Layer::Normal).crop(region) : Image{};
            features[side] = featureRegressors(
                *bases[side], settings.stackAlbedo ? &albedo : nullptr,
                settings.stackNormal ? &normal : nullptr, settings.stackFeatureWindow, &work);
        }
        for (std::size_t q = 0; q < features[0].size(); ++q)
            stacked.push_back({&features[0][q], &features[1][q], &features[2][q]});
    }
    // The regression, weighted by the display slope at the composite.
    const Image weightAtC = settings.space == SureSpace::Linear
                                ? Image{}
                                : tangentWeights(composite, settings.exposure);
    Stacked out;
    out.composite =
        stackComposite(composite, blendA, blendB, stacked, halves.halfA().color().crop(region),
                       halves.halfB().color().crop(region), weightAtC, settings.stackWindow,
                       settings.stackRidge, settings.stackFloor, settings.stackSmooth, &work);
    out.members = int(stacked.size() - features[0].size());
    out.features = int(features[0].size());
    return out;
}

}  // namespace glint::denoise::detail
