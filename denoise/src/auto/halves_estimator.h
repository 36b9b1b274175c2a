// The halves estimator of the automatic selection (docs/auto.md, "Error estimation by
// cross-validation on the halves"): each member filtered on one half of the samples and compared
// with the other. The maps themselves (crossValidationMap, secantCrossValidationMap) are in
// sure.h.
#pragma once

#include <string>
#include <vector>

#include "estimator.h"
#include "glint/denoise/sure.h"

namespace glint::denoise::detail {

/// NaN or Inf in the colour or the half colour: glint::Error(Numeric) naming `file` and the first
/// in scan order.
void checkHalvesFinite(const FrameBuffers& frame, const std::string& file);

/// secantCrossValidationMap with D(centre) given (`displayCentre`, from displayOf): the pipeline
/// computes it once for all the members' maps.
Image secantMap(const Image& halfA, const Image& halfB, const Image& outputA, const Image* outputB,
                const Rect& region, const Image& centre, const std::vector<double>& displayCentre,
                float exposure, SecantForm form, double* unbiasedMean);

/// Cross-validation of every member of `bank` (built from `frame`) on the frame's two halves,
/// over the bank's region, in the error space of options.space: the secant's centred form around
/// `median` (Display), the plain form weighted by `weight` (DisplayTangent; null for Linear) or
/// on display values (DisplayExact).
class HalvesEstimator final : public ErrorEstimator {
  public:
    /// Splits `frame` into its halves, each prefiltered as the bank's input was
    /// (options.prefilter). `bothHalves`: estimate() filters B too (the symmetric form);
    /// `keepResults`: the members' results on the halves are kept for the stacking. `median`
    /// and `displayMedian` are needed for SureSpace::Display only. Everything given must outlive
    /// the estimator.
    HalvesEstimator(const FilterBank& bank, const FrameBuffers& frame, const AutoOptions& options,
                    bool bothHalves, bool keepResults, const Image* median,
                    const std::vector<double>* displayMedian, const Image* weight);
    MemberEstimate estimate(std::size_t member, const ProgressFn& going) override;
    double noiseVariance(int x, int y, int c) const override;

    /// The member filtered on B and its B-side one-sided map (A and B swapped), with the unbiased
    /// mean of the secant's in unbiasedMean (the shortlist).
    MemberEstimate estimateOnB(std::size_t member, const ProgressFn& going);
    /// Forgets the member's results on the halves (a member the shortlist leaves out).
    void dropResults(std::size_t member);

    const FrameBuffers& halfA() const { return m_halfA; }
    const FrameBuffers& halfB() const { return m_halfB; }
    /// The member's result on half A or B (region-sized; with keepResults).
    const Image& onA(std::size_t member) const { return m_onA[member]; }
    const Image& onB(std::size_t member) const { return m_onB[member]; }

  private:
    Image map(const FrameBuffers& on, const FrameBuffers& other, const Image& output,
              const Image* outputOther, std::optional<double>& unbiasedMean) const;

    const FilterBank& m_bank;
    const AutoOptions& m_options;
    bool m_bothHalves, m_keepResults, m_secant;
    const Image* m_median;
    const std::vector<double>* m_displayMedian;
    const Image* m_weight;
    FrameBuffers m_halfA, m_halfB;
    std::vector<Image> m_onA, m_onB;
};

}  // namespace glint::denoise::detail
