// Piecewise-constant 1D and 2D distributions: sample, pdf and inverse (Pharr et al., PBR 3rd ed.,
// sec. 13.3.1 and 14.2.4).
#pragma once

#include <span>
#include <vector>

#include "vecmath.h"

namespace glint::render {

/// A piecewise-constant density on [0, 1) with n equal bins proportional to non-negative values.
class Distribution1D {
  public:
    Distribution1D() = default;
    /// Builds from bin values (negative values are an error; all zeros gives a uniform density).
    explicit Distribution1D(std::span<const float> values);

    int size() const { return int(m_func.size()); }
    /// Integral of the (unnormalised) function over [0, 1).
    double integral() const { return m_integral; }
    /// Unnormalised value of bin i.
    float value(int i) const { return m_func[i]; }

    /// Continuous sample x in [0,1) from u; sets pdf (density in x) and the bin.
    float sampleContinuous(float u, float* pdf, int* bin = nullptr) const;
    /// Discrete sample: a bin with probability value/sum; sets the probability and the reused
    /// uniform remainder in [0,1) if asked.
    int sampleDiscrete(float u, float* probability = nullptr, float* remapped = nullptr) const;
    /// Density at x in [0,1).
    float pdf(float x) const;
    /// Probability of bin i under sampleDiscrete.
    float discretePdf(int i) const;
    /// The u that sampleContinuous maps to x (the CDF at x).
    float invert(float x) const;

  private:
    std::vector<float> m_func;
    std::vector<double> m_cdf;  // size n + 1, m_cdf[n] == 1
    double m_integral = 0.0;
};

/// A piecewise-constant density on [0,1)^2 over an nu × nv grid (row-major, v rows), sampled by
/// the marginal in v and the conditional in u.
class Distribution2D {
  public:
    Distribution2D() = default;
    /// Builds from nu*nv non-negative values, row v at values[v * nu].
    Distribution2D(std::span<const float> values, int nu, int nv);

    bool empty() const { return m_conditional.empty(); }
    int nu() const { return m_nu; }
    int nv() const { return m_nv; }
    /// Point in [0,1)^2 from two uniforms; sets pdf (density with respect to area in uv).
    Vec2 sample(Vec2 u, float* pdf) const;
    /// Density at uv.
    float pdf(Vec2 uv) const;
    /// The uniforms that sample() maps to uv.
    Vec2 invert(Vec2 uv) const;

  private:
    int m_nu = 0, m_nv = 0;
    std::vector<Distribution1D> m_conditional;
    Distribution1D m_marginal;
};

}  // namespace glint::render
