#include "sampling/mlt_sampler.h"

#include <cmath>

#include "glint/render/renderer.h"

namespace glint::render {

const char* mltMutationName(int k) {
    return k >= 0 && k < kMutationKinds ? mutationName(MutationKind(k)) : "?";
}

const char* mutationName(MutationKind kind) {
    switch (kind) {
        case MutationKind::Large:
            return "large";
        case MutationKind::Small:
            return "small";
        case MutationKind::Lens:
            return "lens";
        case MutationKind::Light:
            return "light";
    }
    return "?";
}

MltSampler::Kernel MltSampler::makeKernel(const PerturbationSize& size) {
    Kernel k;
    k.s2 = size.s2;
    const double ratio = double(size.s2) / double(size.s1);
    k.log2Ratio = float(std::log2(ratio));
    // E[dv²] for dv = s2 (s1/s2)^u, u uniform: (s2² − s1²) / (2 ln(s2/s1)).
    const double l = std::log(ratio);
    k.variance = l > 0.0 ? (double(size.s2) * size.s2 - double(size.s1) * size.s1) / (2.0 * l)
                         : double(size.s2) * size.s2;
    return k;
}

MltSampler::MltSampler(std::uint64_t key, const MutationSizes& sizes)
    : m_rng(key),
      m_small(makeKernel(sizes.small)),
      m_lensX(makeKernel(sizes.lensX)),
      m_lensY(makeKernel(sizes.lensY)),
      m_light(makeKernel(sizes.light)) {
    m_x.reserve(64);
    m_touchedList.reserve(64);
}

void MltSampler::startIteration(MutationKind kind) {
    ++m_iteration;
    m_kind = kind;
    ++m_count[int(kind)];
    m_touchedList.clear();
    m_pathIndex = m_lightIndex = 0;
}

void MltSampler::accept() {
    if (m_kind == MutationKind::Large) {
        // Every coordinate not read by this path is now stale: it will be drawn afresh.
        m_lastLarge = m_iteration;
        m_countAtLarge = m_count;
    }
}

void MltSampler::reject() {
    // The rejected step never happened: only accepted steps count as pending perturbations of
    // coordinates the path did not read, exactly as if every coordinate had been perturbed and
    // restored (an eager update). Counting rejected iterations too would make the step size
    // grow while the chain is stuck, a history-dependent proposal that under-samples bright
    // states.
    --m_count[int(m_kind)];
    for (const std::uint32_t i : m_touchedList) {
        Coordinate& c = m_x[i];
        c.value = c.backupValue;
        c.largeIteration = c.backupLarge;
        c.seen = c.backupSeen;
    }
}

void MltSampler::setCamera(int dim, float value) {
    const auto index = std::size_t(dim);
    if (index >= m_x.size()) m_x.resize(index + 1);
    get(index, Stream::Camera);  // backs up and materialises the coordinate for this iteration
    m_x[index].value = value;
}

float MltSampler::getSlow(std::size_t index, Stream stream) {
    if (index >= m_x.size()) m_x.resize(index + 1);
    Coordinate& c = m_x[index];
    if (c.touched == m_iteration) return c.value;

    // Back up the state before this proposal (possibly stale: a stale value is "any uniform").
    backup(c, index);

    // Large step, or a coordinate untouched since the last accepted large step replaced the
    // whole vector: a fresh uniform number (perturbing a uniform number keeps it uniform).
    if (m_kind == MutationKind::Large || c.largeIteration < m_lastLarge) {
        c.value = m_rng.uniform();
        c.largeIteration = m_kind == MutationKind::Large ? m_iteration : m_lastLarge;
        c.seen = m_count;
        return c.value;
    }

    // Catch up with every mutation since the coordinate was last read, this one included: all
    // small steps; lens perturbations for film and lens coordinates; light perturbations for
    // the light stream (Kelemen et al. 2002, sec. 4: lazy evaluation of mutations).
    constexpr int kSmall = int(MutationKind::Small), kLens = int(MutationKind::Lens),
                  kLight = int(MutationKind::Light);
    const std::uint32_t nSmall = m_count[kSmall] - c.seen[kSmall];
    std::uint32_t nOther = 0;
    const Kernel* other = nullptr;
    if (stream == Stream::Light) {
        nOther = m_count[kLight] - c.seen[kLight];
        other = &m_light;
    } else if (stream == Stream::Camera && index <= std::size_t(kLensV)) {
        nOther = m_count[kLens] - c.seen[kLens];
        other = index == std::size_t(kFilmX)   ? &m_lensX
                : index == std::size_t(kFilmY) ? &m_lensY
                                               : &m_small;
    }
    c.value = catchUp(c.value, nSmall, nOther, other);
    c.seen = m_count;
    return c.value;
}

float MltSampler::catchUp(float x, std::uint32_t nSmall, std::uint32_t nOther,
                          const Kernel* other) {
    constexpr std::uint32_t kExactSteps = 8;
    if (nSmall + nOther <= kExactSteps) {
        // Kelemen et al. 2002, sec. 4: dv = s2 exp(−ln(s2/s1) u), added or subtracted with
        // equal probability, wrapped around the unit interval (a symmetric proposal).
        for (std::uint32_t i = 0; i < nSmall; ++i) x = step(x, m_small);
        for (std::uint32_t i = 0; i < nOther; ++i) x = step(x, *other);
        return x;
    }
    // Many pending steps (the coordinate went unused for a while): their sum is close to a
    // Gaussian of the summed variance (central limit theorem); still a symmetric proposal.
    double variance = double(nSmall) * m_small.variance;
    if (other) variance += double(nOther) * other->variance;
    // Box–Muller transform.
    const double u1 = 1.0 - m_rng.uniformDouble(), u2 = m_rng.uniformDouble();
    const double g = std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
    double y = double(x) + g * std::sqrt(variance);
    y -= std::floor(y);
    const float r = float(y);
    return r < 1.0f ? r : 0.0f;
}

}  // namespace glint::render
