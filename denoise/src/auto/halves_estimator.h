// The halves estimator of the automatic selection (docs/auto.md, "Error estimation by
// cross-validation on the halves"): each member filtered on one half of the samples and compared
// with the other. The maps (crossValidationMap, secantCrossValidationMap) and the estimator over
// a bank.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "estimator.h"
#include "glint/denoise/auto.h"
#include "options.h"

namespace glint::denoise::detail {

/// Per-pixel cross-validation error over `region`, summed over the channels (1 channel,
/// region-sized), from two independent halves A and B of the samples (frame-sized colours)
/// and a filter's outputs on each (region-sized; `outputB` may be null):
///   symmetric:  Σ_c weight_c [(f(A) − B)² + (f(B) − A)² − (A − B)²] / 2,
///   one-sided:  Σ_c weight_c [(f(A) − B)² − (A − B)² / 2].
/// As B is independent of A and of f(A), E(f(A) − B)² = MSE f(A) + Var B; the symmetric form is
/// an unbiased estimate of the filter's mean squared error on a half, the one-sided one of
/// MSE f(A) + (Var B − Var A)/2 (the same for equal halves). No noise model, no variance layer
/// and no divergence: it holds for the heavy-tailed, guide-correlated noise of a render.
/// With `displayExposure`, every value (halves and outputs) is first mapped by the display
/// transform (exposure, clamp, sRGB) and `weight` must be null: the estimate is then of the
/// display error up to a term that is the product of the filter's and B's display biases
/// (E[D(f(A)) − D(x)]·E[D(x) − D(B)], independent factors), small where either is.
Image crossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                         const Image* outputB, const Rect& region, const Image* weight = nullptr,
                         std::optional<float> displayExposure = std::nullopt);

/// The halves' display-space error map (SureSpace::Display): as crossValidationMap, but each
/// side's term is weighted by the squared secant slope s² of the display transform D (exposure,
/// clamp, sRGB) between that output and `centre` (region-sized, 3 channels: a member-independent
/// estimate of the clean value, the median of the bank), s = (D(f) − D(m)) / (f − m) (the slope
/// at m where f ≈ m; 0 where both are clamped, as their display values agree there):
///   symmetric:  Σ_c ½ [s_A² ((f(A) − B)² − ½(A − B)²) + s_B² ((f(B) − A)² − ½(A − B)²)],
///   one-sided:  Σ_c s_A² ((f(A) − B)² − ½(A − B)²).
/// s_A depends on B only through the median of many filtered results, so the first term
/// estimates s_A² · MSE f(A) nearly without bias; and the linearisation is first-order in
/// x − m only, where the tangent's is in f − m too, which is large exactly where a filter
/// blurs a highlight or a firefly.
///
/// SecantForm::Centred writes each side's term as s² (f − m)(f + m − 2B) = s² [(f − B)² −
/// (m − B)²] instead (A and B swapped for f(B)): its expectation is s² [MSE f − (m − x)²],
/// the member's error less the centre's own, weighed alike, so it ranks the members as the
/// unbiased form does up to the spread of s² between them. But its noise, −2 s² (f − m)(B − x),
/// vanishes as f nears m, where the unbiased form's holds s² [(B − x)² − Var B] for every
/// member: with s² differing between two members, a firefly in B does not cancel out of their
/// difference (docs/auto.md, "Error estimation by cross-validation on the halves").
/// `unbiasedMean`, when given, receives the unbiased form's mean per pixel and channel over the
/// region (as if `form` were Unbiased), which is what the centred map's mean is not: an estimate
/// of the member's display MSE.
enum class SecantForm { Unbiased, Centred };
Image secantCrossValidationMap(const Image& halfA, const Image& halfB, const Image& outputA,
                               const Image* outputB, const Rect& region, const Image& centre,
                               float exposure = 0.0f, SecantForm form = SecantForm::Unbiased,
                               double* unbiasedMean = nullptr);

/// NaN or Inf in the colour or the half colour: glint::Error(Numeric) naming `file` and the first
/// in scan order.
void checkHalvesFinite(const FrameBuffers& frame, const std::string& file);

/// secantCrossValidationMap with D(centre) given (`displayCentre`, from displayOf): the pipeline
/// computes it once for all the members' maps. `unbiasedRows`, when given, receives the sum of
/// the unbiased terms of each row of the region (the pipeline adds its tiles' rows
/// up in the same order).
Image secantMap(const Image& halfA, const Image& halfB, const Image& outputA, const Image* outputB,
                const Rect& region, const Image& centre, const std::vector<double>& displayCentre,
                float exposure, SecantForm form, double* unbiasedMean,
                std::vector<double>* unbiasedRows = nullptr);

/// Cross-validation of every member of `bank` (built from `frame`) on the frame's two halves,
/// over the bank's region, in the error space of settings.space: the secant's centred form around
/// `median` (Display), the plain form weighted by `weight` (DisplayTangent; null for Linear) or
/// on display values (DisplayExact).
class HalvesEstimator final : public ErrorEstimator {
  public:
    /// Splits `frame` into its halves, each prefiltered as the bank's input was
    /// (settings.prefilter). `bothHalves`: estimate() filters B too (the symmetric form).
    /// `median` and `displayMedian` are needed for SureSpace::Display only. Everything given
    /// must outlive the estimator.
    HalvesEstimator(const FilterBank& bank, const FrameBuffers& frame, const AutoSettings& settings,
                    bool bothHalves, const Image* median, const std::vector<double>* displayMedian,
                    const Image* weight);
    MemberEstimate estimate(std::size_t member, const ProgressFn& going) override;
    double noiseVariance(int x, int y, int c) const override;

    /// The map of one side from the outputs on it (and on the other side, symmetric; null:
    /// one-sided) over `region`, a part of the bank's (`centre` and `displayCentre` the
    /// median's over it, for the secant): estimate()'s map, for the pipeline's tiles, with
    /// the unbiased terms' row sums in `unbiasedRows` (the secant's).
    Image mapOver(const Rect& region, bool onA, const Image& output, const Image* outputOther,
                  const Image* centre, const std::vector<double>* displayCentre,
                  const Image* weight, std::vector<double>& unbiasedRows) const;

    const FrameBuffers& halfA() const { return m_halfA; }
    const FrameBuffers& halfB() const { return m_halfB; }

  private:
    Image map(const FrameBuffers& on, const FrameBuffers& other, const Image& output,
              const Image* outputOther, std::optional<double>& unbiasedMean) const;

    const FilterBank& m_bank;
    const AutoSettings& m_settings;
    bool m_bothHalves, m_secant;
    const Image* m_median;
    const std::vector<double>* m_displayMedian;
    const Image* m_weight;
    FrameBuffers m_halfA, m_halfB;
};

}  // namespace glint::denoise::detail
