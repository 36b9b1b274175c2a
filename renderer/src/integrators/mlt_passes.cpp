#include "integrators/mlt_passes.h"

#include <algorithm>
#include <cmath>

#include "integrators/mlt_integrator.h"
#include "sampling/rng.h"

namespace glint::render {

namespace {

using Clock = std::chrono::steady_clock;

// Stream slots of streamKey(seed, slot, index) reserved for Metropolis; pixel indices of the
// path tracer stay far below 2^63, so the streams never coincide.
constexpr std::uint64_t kBootstrapSlot = (1ULL << 63) | 1;
constexpr std::uint64_t kChainSlot = (1ULL << 63) | 2;
constexpr std::uint64_t kPickSlot = (1ULL << 63) | 3;

/// Bootstrap samples per work item of the preparatory pass.
constexpr std::int64_t kBootstrapBlock = 1024;

}  // namespace

MltPasses::MltPasses(const MltIntegrator& integrator, int width, int height,
                     const MltPassSettings& s, const FrameBuffers& features)
    : m_integrator(integrator),
      m_width(width),
      m_height(height),
      m_pixels(std::size_t(width) * std::size_t(height)),
      m_s(s),
      m_features(features),
      m_start(Clock::now()),
      m_bootF(std::size_t(s.bootstrap), 0.0f),
      m_bootRays(std::size_t((s.bootstrap + kBootstrapBlock - 1) / kBootstrapBlock), 0),
      m_bootTaken(m_bootRays.size(), 0),
      m_bootNonFinite(m_bootRays.size(), 0),
      m_groups(std::size_t(s.groups)) {}

std::size_t MltPasses::setupItems() const {
    return m_bootRays.size();
}

double MltPasses::setupSpp() const {
    // A bootstrap sample costs about what a mutation does; a pass takes `count` of them a pixel.
    return double(m_s.bootstrap) / double(m_pixels);
}

void MltPasses::startBootstrapSample(MltSampler& sampler, std::int64_t i) const {
    // Bootstrap sample i has its film point stratified: stratum i of N equal intervals of the
    // film in scanline order (x jittered inside its pixel along the scan, y uniform). Each point
    // stays uniform over the film, but the estimate of b no longer carries the variance of
    // where bright things (a visible light) are on screen.
    const std::int64_t nBoot = m_s.bootstrap;
    sampler.startIteration(MutationKind::Large);
    const double s =
        (double(i) + double(sampler.rng().uniform())) / double(nBoot) * double(m_pixels);
    const double pixel = std::min(std::floor(s), double(m_pixels) - 1.0);
    const auto pi = std::uint64_t(pixel);
    const double fx = (double(pi % std::uint64_t(m_width)) + (s - pixel)) / double(m_width);
    sampler.setCamera(kFilmX, std::min(float(fx), 0x1.fffffep-1f));
    const double fy =
        (double(pi / std::uint64_t(m_width)) + sampler.camera(kFilmY)) / double(m_height);
    sampler.setCamera(kFilmY, std::min(float(fy), 0x1.fffffep-1f));
}

void MltPasses::runSetup(std::size_t block, const RenderLoop&) {
    const std::int64_t begin = std::int64_t(block) * kBootstrapBlock;
    const std::int64_t end = std::min(m_s.bootstrap, begin + kBootstrapBlock);
    for (std::int64_t i = begin; i < end; ++i) {
        MltSampler sampler(streamKey(m_s.seed, kBootstrapSlot, std::uint64_t(i)), m_s.sizes);
        startBootstrapSample(sampler, i);
        Vec3 l;
        Vec2 r;
        m_integrator.evaluate(sampler, l, r, m_bootRays[block], m_bootNonFinite[block]);
        m_bootF[std::size_t(i)] = std::max(0.0f, luminance(l));
    }
    m_bootTaken[block] = std::uint64_t(end - begin);
}

bool MltPasses::setupCompleted() {
    const std::int64_t nBoot = m_s.bootstrap;
    std::vector<double> cdf(std::size_t(nBoot) + 1, 0.0);
    for (std::int64_t i = 0; i < nBoot; ++i)
        cdf[std::size_t(i) + 1] = cdf[std::size_t(i)] + m_bootF[std::size_t(i)];
    const double b = cdf.back() / double(nBoot);
    m_b = b;
    if (b > 0.0 && nBoot > 1) {
        // Standard error of a stratified mean from differences of neighbouring strata:
        // Var(b) ≈ Σ_k (f_2k − f_2k+1)² / N² (pairs of adjacent strata; slightly conservative).
        double pairSum = 0.0;
        for (std::int64_t i = 0; i + 1 < nBoot; i += 2) {
            const double d = double(m_bootF[std::size_t(i)]) - m_bootF[std::size_t(i) + 1];
            pairSum += d * d;
        }
        const double pairs = double(nBoot / 2);
        m_bRelStdErr = std::sqrt(pairSum / pairs * (double(nBoot) / 2.0)) / double(nBoot) / b;
    }
    m_invB = b > 0.0 ? float(1.0 / b) : 0.0f;
    // Chains start from bootstrap samples drawn in proportion to f (resampling removes start-up
    // bias); each reproduces its sample in the first pass (startChains).
    if (b > 0.0) {
        m_chains.reserve(std::size_t(m_s.chains));
        for (int c = 0; c < m_s.chains; ++c) {
            Rng pick(streamKey(m_s.seed, kPickSlot, std::uint64_t(c)));
            const double target = pick.uniformDouble() * cdf.back();
            auto it = std::upper_bound(cdf.begin() + 1, cdf.end(), target);
            std::size_t index = std::size_t(it - cdf.begin()) - 1;
            index = std::min(index, std::size_t(nBoot) - 1);
            m_chains.push_back({MltSampler(streamKey(m_s.seed, kBootstrapSlot, index), m_s.sizes),
                                std::int64_t(index),
                                {},
                                {},
                                0.0f});
        }
    }
    for (Group& g : m_groups) g.sum.assign(m_pixels * 3, 0.0);
    m_bootSeconds = std::chrono::duration<double>(Clock::now() - m_start).count();
    m_bootDone = true;
    return !m_chains.empty();
}

void MltPasses::startChains(std::size_t g) {
    // Each chain is reproduced exactly from its bootstrap sample's stream, then continued with
    // its own stream (seed, chain index).
    Group& group = m_groups[g];
    const int nChains = int(m_chains.size()), nGroups = int(m_groups.size());
    for (int c = int(g); c < nChains; c += nGroups) {
        Chain& chain = m_chains[std::size_t(c)];
        startBootstrapSample(chain.sampler, chain.bootstrapIndex);
        m_integrator.evaluate(chain.sampler, chain.radiance, chain.raster, group.rays,
                              group.nonFinite);
        chain.sampler.accept();
        chain.sampler.reseed(streamKey(m_s.seed, kChainSlot, std::uint64_t(c)));
        chain.f = std::max(0.0f, luminance(chain.radiance));
    }
    group.started = true;
}

std::uint64_t MltPasses::perChain(const PassInfo& pass) const {
    const auto n = std::uint64_t(m_chains.size());
    return (std::uint64_t(pass.count) * std::uint64_t(m_pixels) + n - 1) / n;
}

void MltPasses::run(const PassInfo& pass, std::size_t g, const RenderLoop& loop) {
    const int width = m_width, height = m_height;
    const int nChains = int(m_chains.size()), nGroups = int(m_groups.size());
    const std::uint64_t steps = perChain(pass);
    Group& group = m_groups[g];
    if (!group.started) startChains(g);
    for (int c = int(g); c < nChains; c += nGroups) {
        if (loop.stopRequested()) return;
        Chain& ch = m_chains[std::size_t(c)];
        MltSampler& sampler = ch.sampler;
        auto splat = [&](Vec2 raster, const Vec3& value) {
            const int x = std::min(int(raster.x), width - 1);
            const int y = std::min(int(raster.y), height - 1);
            double* px = &group.sum[3 * (std::size_t(y) * width + x)];
            px[0] += value.x, px[1] += value.y, px[2] += value.z;
        };
        for (std::uint64_t i = 0; i < steps; ++i) {
            // Choose and propose a mutation.
            const float uKind = sampler.rng().uniform();
            int kind = 0;
            while (uKind >= m_s.cdf[kind]) ++kind;
            sampler.startIteration(MutationKind(kind));
            Vec3 ly;
            Vec2 ry;
            m_integrator.evaluate(sampler, ly, ry, group.rays, group.nonFinite);
            const float fy = std::max(0.0f, luminance(ly));
            const float a = ch.f > 0.0f ? std::min(1.0f, fy / ch.f) : 1.0f;
            // Splat both states with their expected weights, combined with the large step as an
            // independent estimator (Kelemen et al. 2002, sec. 5: weights
            // (a + [large]) / (f(y)/b + p_large) for the proposal and
            // (1 − a) / (f(x)/b + p_large) for the current).
            const float large = kind == 0 ? 1.0f : 0.0f;
            if (fy > 0.0f) splat(ry, ly * ((a + large) / (fy * m_invB + m_s.pLarge)));
            if (a < 1.0f && ch.f > 0.0f)
                splat(ch.raster, ch.radiance * ((1.0f - a) / (ch.f * m_invB + m_s.pLarge)));
            ++group.proposed[std::size_t(kind)];
            // Metropolis–Hastings acceptance with a symmetric proposal.
            if (sampler.rng().uniform() < a) {
                sampler.accept();
                ++group.accepted[std::size_t(kind)];
                ch.radiance = ly;
                ch.raster = ry;
                ch.f = fy;
            } else {
                sampler.reject();
            }
        }
    }
}

void MltPasses::passCompleted(const PassInfo& pass) {
    m_perChainDone += perChain(pass);
    m_snapshot = resolve();
    m_snapshot.metadata().spp = pass.first + pass.count;
}

FrameBuffers MltPasses::resolve() const {
    // Pixel value of a group: (pixels / M_g) Σ splats (Kelemen et al. 2002, sec. 5, with a box
    // pixel filter); the image is the mean of the group images and its variance of the mean the
    // batch-means estimate Σ (I_g − Ī)² / (K (K − 1)).
    FrameBuffers frame = m_features;
    Image& color = frame.color();
    Image& variance = frame.ensure(Layer::Variance);
    const int width = frame.width();
    const std::size_t pixels = std::size_t(width) * std::size_t(frame.height());
    const double mg = double(m_perChainDone) * double(m_chains.size() / m_groups.size());
    const double scale = double(m_pixels) / mg;
    const double k = double(m_groups.size());
    for (std::size_t p = 0; p < pixels; ++p)
        for (int c = 0; c < 3; ++c) {
            double s = 0.0, s2 = 0.0;
            for (const Group& g : m_groups) s += g.sum[3 * p + std::size_t(c)] * scale;
            const double mean = s / k;
            for (const Group& g : m_groups) {
                const double d = g.sum[3 * p + std::size_t(c)] * scale - mean;
                s2 += d * d;
            }
            const int x = int(p % std::size_t(width)), y = int(p / std::size_t(width));
            color(x, y, c) = float(mean);
            variance(x, y, c) = float(s2 / (k * (k - 1.0)));
        }
    return frame;
}

double MltPasses::chainsRelStdErr() const {
    // Each group's image is an estimate of the whole image given b; the spread of the groups'
    // mean luminances is the chains' part of the error of the image's mean (batch means).
    const std::size_t k = m_groups.size();
    if (m_perChainDone == 0 || k < 2) return 0.0;
    std::vector<double> means(k, 0.0);
    for (std::size_t g = 0; g < k; ++g) {
        const std::vector<double>& sum = m_groups[g].sum;
        double r = 0.0, gr = 0.0, bl = 0.0;
        for (std::size_t p = 0; p < m_pixels; ++p)
            r += sum[3 * p], gr += sum[3 * p + 1], bl += sum[3 * p + 2];
        means[g] = 0.2126 * r + 0.7152 * gr + 0.0722 * bl;  // luminance() in double
    }
    double mean = 0.0, s2 = 0.0;
    for (double m : means) mean += m / double(k);
    for (double m : means) s2 += (m - mean) * (m - mean);
    return mean > 0.0 ? std::sqrt(s2 / (double(k) * double(k - 1))) / mean : 0.0;
}

void MltPasses::addStatistics(MltStats& stats, std::uint64_t& rays, std::int64_t& nonFinite) const {
    stats.b = m_b;
    stats.bRelStdErr = m_bRelStdErr;
    for (std::size_t k = 0; k < m_bootRays.size(); ++k) {
        stats.bootstrap += m_bootTaken[k];
        rays += m_bootRays[k];
        nonFinite += m_bootNonFinite[k];
    }
    for (const Group& g : m_groups) {
        for (int k = 0; k < kMutationKinds; ++k)
            stats.proposed[std::size_t(k)] += g.proposed[std::size_t(k)],
                stats.accepted[std::size_t(k)] += g.accepted[std::size_t(k)];
        rays += g.rays;
        nonFinite += g.nonFinite;
    }
    stats.mutations = m_perChainDone * std::uint64_t(m_chains.size());
}

}  // namespace glint::render
