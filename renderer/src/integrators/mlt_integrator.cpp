#include "integrators/mlt_integrator.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <string>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include "glint/image/error.h"

namespace glint::render {

namespace {

using Clock = std::chrono::steady_clock;

// Stream slots of streamKey(seed, slot, index) reserved for Metropolis; pixel indices of the
// path tracer stay far below 2^63, so the streams never coincide.
constexpr std::uint64_t kBootstrapSlot = (1ULL << 63) | 1;
constexpr std::uint64_t kChainSlot = (1ULL << 63) | 2;
constexpr std::uint64_t kPickSlot = (1ULL << 63) | 3;

std::string formatDouble(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// One Markov chain: its primary sample vector and the current state's contribution.
struct Chain {
    MltSampler sampler;
    std::int64_t bootstrapIndex;  // the bootstrap sample it started from
    Vec3 radiance;
    Vec2 raster;
    float f = 0.0f;  // target: luminance of the contribution
};

/// The splats of one batch of chains (accumulated in double) and its counters.
struct Group {
    std::vector<double> sum;  // width × height × 3
    std::array<std::uint64_t, kMutationKinds> proposed{}, accepted{};
    std::uint64_t rays = 0;
    std::int64_t nonFinite = 0;
};

}  // namespace

void validateMlt(const MltSettings& m) {
    auto fail = [](const std::string& what) {
        throw Error(ErrorKind::InvalidArgument, "mlt: " + what);
    };
    for (const double p : {m.largeStep, m.smallStep, m.lens, m.light})
        if (!(p >= 0.0) || !std::isfinite(p))
            fail("mutation probabilities must be finite and >= 0");
    if (!(m.largeStep + m.smallStep + m.lens + m.light > 0.0))
        fail("at least one mutation probability must be > 0");
    if (!(m.s1 > 0.0 && m.s1 <= m.s2 && m.s2 <= 0.5))
        fail("small-step sizes must satisfy 0 < s1 <= s2 <= 0.5");
    if (!(m.lightS1 > 0.0 && m.lightS1 <= m.lightS2 && m.lightS2 <= 0.5))
        fail("light perturbation sizes must satisfy 0 < lightS1 <= lightS2 <= 0.5");
    if (!(m.lensS1 > 0.0 && m.lensS1 <= m.lensS2))
        fail("lens perturbation sizes must satisfy 0 < lensS1 <= lensS2 (pixels)");
    if (m.bootstrap < 1) fail("bootstrap must be >= 1");
    if (m.groups < 2) fail("groups must be >= 2 (batch-means variance)");
    if (m.chains < m.groups || m.chains % m.groups != 0)
        fail("chains (" + std::to_string(m.chains) + ") must be a multiple of groups (" +
             std::to_string(m.groups) + ")");
    if (m.featureSpp < 1) fail("featureSpp must be >= 1");
}

Settings mltFeatureSettings(const Settings& settings) {
    Settings s = settings;
    s.integrator = Integrator::Path;
    s.spp = settings.mlt.featureSpp;
    s.timeLimit = 0.0;
    return s;
}

MltIntegrator::MltIntegrator(const detail::SceneData& scene, const EmbreeScene& embree,
                             const LightSampler& lights, const Camera& camera,
                             const Settings& settings)
    : m_scene(scene),
      m_camera(camera),
      m_lights(lights),
      m_settings(settings),
      m_path(scene, embree, lights, camera, settings),
      m_thinLens(scene.camera.lensRadius > 0.0f),
      m_sampleTime(scene.hasMotion() && scene.camera.shutterClose > scene.camera.shutterOpen) {
    validateMlt(settings.mlt);
}

void MltIntegrator::evaluate(MltSampler& sampler, Vec3& radiance, Vec2& raster, std::uint64_t& rays,
                             std::int64_t& nonFinite) const {
    // The reserved camera coordinates; lens and time are read only when they matter.
    raster = {sampler.camera(kFilmX) * float(m_scene.width),
              sampler.camera(kFilmY) * float(m_scene.height)};
    Vec2 lens{0.5f, 0.5f};
    if (m_thinLens) lens = {sampler.camera(kLensU), sampler.camera(kLensV)};
    const float time = m_sampleTime ? sampler.camera(kTime) : 0.0f;
    const Ray ray = m_camera.generateRay(raster.x, raster.y, lens, time);
    FilmSample sample;
    m_path.trace(ray, sampler, sample, rays);
    radiance = sample.color;
    if (!isFinite(radiance) || !std::isfinite(luminance(radiance))) {
        // A NaN/Inf path is discarded: it has zero contribution and is never accepted.
        ++nonFinite;
        radiance = {};
    }
}

FrameBuffers MltIntegrator::render(FrameBuffers features, const Callbacks& callbacks,
                                   tbb::task_arena& arena, double timeBudget, double progressBegin,
                                   RenderStats& stats) {
    const MltSettings& mlt = m_settings.mlt;
    const int width = m_scene.width, height = m_scene.height;
    const std::size_t pixels = std::size_t(width) * std::size_t(height);
    const std::uint64_t seed = m_settings.seed;
    const Clock::time_point start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    MltStats ms;

    MutationSizes sizes;
    sizes.small = {float(mlt.s1), float(mlt.s2)};
    sizes.lensX = {float(mlt.lensS1 / width), float(mlt.lensS2 / width)};
    sizes.lensY = {float(mlt.lensS1 / height), float(mlt.lensS2 / height)};
    sizes.light = {float(mlt.lightS1), float(mlt.lightS2)};

    // Mutation choice: cumulative probabilities. A scene without next-event estimation has no
    // light-stream numbers, so its light perturbation would be a no-op: it is left out.
    const bool neeUsed = !m_lights.empty() && (m_settings.mis != MisHeuristic::None ||
                                               m_settings.strategy == Strategy::Light);
    std::array<double, kMutationKinds> weight = {mlt.largeStep, mlt.smallStep, mlt.lens,
                                                 neeUsed ? mlt.light : 0.0};
    double weightSum = 0.0;
    for (double w : weight) weightSum += w;
    if (!(weightSum > 0.0))
        throw Error(ErrorKind::InvalidArgument,
                    "mlt: the scene has no light sampling and the only mutation is 'light'");
    std::array<float, kMutationKinds> cdf{};
    double acc = 0.0;
    for (int k = 0; k < kMutationKinds; ++k) cdf[k] = float((acc += weight[k]) / weightSum);
    cdf[kMutationKinds - 1] = 2.0f;  // uniform() < 1 always lands somewhere
    const float pLarge = float(weight[0] / weightSum);

    // 1. Bootstrap (Kelemen et al. 2002, sec. 5; Veach 1997, sec. 11.3.1): N independent
    //    uniform primary samples estimate b = ∫ f, the image's mean luminance.
    const std::int64_t nBoot = mlt.bootstrap;
    // Bootstrap sample i has its film point stratified: stratum i of N equal intervals of the
    // film in scanline order (x jittered inside its pixel along the scan, y uniform). Each point
    // stays uniform over the film, but the estimate of b no longer carries the variance of
    // where bright things (a visible light) are on screen.
    auto startBootstrapSample = [&](MltSampler& sampler, std::int64_t i) {
        sampler.startIteration(MutationKind::Large);
        const double s =
            (double(i) + double(sampler.rng().uniform())) / double(nBoot) * double(pixels);
        const double pixel = std::min(std::floor(s), double(pixels) - 1.0);
        const auto pi = std::uint64_t(pixel);
        const double fx = (double(pi % std::uint64_t(width)) + (s - pixel)) / double(width);
        sampler.setCamera(kFilmX, std::min(float(fx), 0x1.fffffep-1f));
        const double fy =
            (double(pi / std::uint64_t(width)) + sampler.camera(kFilmY)) / double(height);
        sampler.setCamera(kFilmY, std::min(float(fy), 0x1.fffffep-1f));
    };
    std::vector<float> bootF(std::size_t(nBoot), 0.0f);
    std::vector<std::uint64_t> bootRays(std::size_t((nBoot + 1023) / 1024), 0);
    std::vector<std::int64_t> bootNonFinite(bootRays.size(), 0);
    arena.execute([&] {
        tbb::parallel_for(std::size_t(0), bootRays.size(), [&](std::size_t block) {
            const std::int64_t end = std::min<std::int64_t>(nBoot, std::int64_t(block + 1) * 1024);
            for (std::int64_t i = std::int64_t(block) * 1024; i < end; ++i) {
                MltSampler sampler(streamKey(seed, kBootstrapSlot, std::uint64_t(i)), sizes);
                startBootstrapSample(sampler, i);
                Vec3 l;
                Vec2 r;
                evaluate(sampler, l, r, bootRays[block], bootNonFinite[block]);
                bootF[std::size_t(i)] = std::max(0.0f, luminance(l));
            }
        });
    });
    std::vector<double> bootCdf(std::size_t(nBoot) + 1, 0.0);
    for (std::int64_t i = 0; i < nBoot; ++i) {
        bootCdf[std::size_t(i) + 1] = bootCdf[std::size_t(i)] + bootF[std::size_t(i)];
    }
    const double b = bootCdf.back() / double(nBoot);
    ms.b = b;
    ms.bootstrap = std::uint64_t(nBoot);
    if (b > 0.0 && nBoot > 1) {
        // Standard error of a stratified mean from differences of neighbouring strata:
        // Var(b) ≈ Σ_k (f_2k − f_2k+1)² / N² (pairs of adjacent strata; slightly conservative).
        double pairSum = 0.0;
        for (std::int64_t i = 0; i + 1 < nBoot; i += 2) {
            const double d = double(bootF[std::size_t(i)]) - bootF[std::size_t(i) + 1];
            pairSum += d * d;
        }
        const double pairs = double(nBoot / 2);
        ms.bRelStdErr = std::sqrt(pairSum / pairs * (double(nBoot) / 2.0)) / double(nBoot) / b;
    }
    std::uint64_t rays = 0;
    std::int64_t nonFinite = 0;
    for (std::size_t k = 0; k < bootRays.size(); ++k)
        rays += bootRays[k], nonFinite += bootNonFinite[k];

    // 2. Chains start from bootstrap samples drawn in proportion to f (resampling removes
    //    start-up bias), each reproduced exactly from the bootstrap sample's stream and then
    //    continued with its own stream (seed, chain index).
    const int nChains = mlt.chains, nGroups = mlt.groups;
    std::vector<Chain> chains;
    std::vector<Group> groups(static_cast<std::size_t>(nGroups));
    if (b > 0.0) {
        chains.reserve(std::size_t(nChains));
        for (int c = 0; c < nChains; ++c) {
            Rng pick(streamKey(seed, kPickSlot, std::uint64_t(c)));
            const double target = pick.uniformDouble() * bootCdf.back();
            auto it = std::upper_bound(bootCdf.begin() + 1, bootCdf.end(), target);
            std::size_t index = std::size_t(it - bootCdf.begin()) - 1;
            index = std::min(index, std::size_t(nBoot) - 1);
            chains.push_back({MltSampler(streamKey(seed, kBootstrapSlot, index), sizes),
                              std::int64_t(index),
                              {},
                              {},
                              0.0f});
        }
        arena.execute([&] {
            tbb::parallel_for(0, nGroups, [&](int g) {
                Group& group = groups[std::size_t(g)];
                for (int c = g; c < nChains; c += nGroups) {
                    Chain& chain = chains[std::size_t(c)];
                    startBootstrapSample(chain.sampler, chain.bootstrapIndex);
                    evaluate(chain.sampler, chain.radiance, chain.raster, group.rays,
                             group.nonFinite);
                    chain.sampler.accept();
                    chain.sampler.reseed(streamKey(seed, kChainSlot, std::uint64_t(c)));
                    chain.f = std::max(0.0f, luminance(chain.radiance));
                }
            });
        });
    }
    for (Group& g : groups) g.sum.assign(pixels * 3, 0.0);

    // 3. Passes (the shared RenderLoop): every chain advances by the same number of mutations
    //    (spp-equivalent pass sizes 1, 1, 2, 4, ... 64 as in the path tracer); groups run in
    //    parallel, the chains of a group one after another in index order, so every sum has a
    //    fixed order.
    const double bootSeconds = elapsed();
    const bool timed = timeBudget > 0.0;
    const int spp = m_settings.spp;
    const float invB = b > 0.0 ? float(1.0 / b) : 0.0f;
    const double fullScale = double(pixels);

    // The work of one pass for the loop: item g advances the chains of group g.
    class ChainPasses final : public PassWork {
      public:
        ChainPasses(MltIntegrator& self, std::vector<Chain>& chains, std::vector<Group>& groups,
                    const FrameBuffers& features, const std::array<float, kMutationKinds>& cdf,
                    float pLarge, float invB, double fullScale)
            : m_self(self),
              m_chains(chains),
              m_groups(groups),
              m_features(features),
              m_cdf(cdf),
              m_pLarge(pLarge),
              m_invB(invB),
              m_fullScale(fullScale) {}

        std::size_t items() const override { return m_groups.size(); }

        std::uint64_t perChain(const PassInfo& pass) const {
            const std::uint64_t pixels =
                std::uint64_t(m_self.m_scene.width) * std::uint64_t(m_self.m_scene.height);
            const auto n = std::uint64_t(m_chains.size());
            return (std::uint64_t(pass.count) * pixels + n - 1) / n;
        }

        void run(const PassInfo& pass, std::size_t g, const RenderLoop& loop) override {
            const int width = m_self.m_scene.width, height = m_self.m_scene.height;
            const int nChains = int(m_chains.size()), nGroups = int(m_groups.size());
            const std::uint64_t steps = perChain(pass);
            Group& group = m_groups[g];
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
                    while (uKind >= m_cdf[kind]) ++kind;
                    sampler.startIteration(MutationKind(kind));
                    Vec3 ly;
                    Vec2 ry;
                    m_self.evaluate(sampler, ly, ry, group.rays, group.nonFinite);
                    const float fy = std::max(0.0f, luminance(ly));
                    const float a = ch.f > 0.0f ? std::min(1.0f, fy / ch.f) : 1.0f;
                    // Splat both states with their expected weights, combined with the large
                    // step as an independent estimator (Kelemen et al. 2002, sec. 5: weights
                    // (a + [large]) / (f(y)/b + p_large) for the proposal and
                    // (1 − a) / (f(x)/b + p_large) for the current).
                    const float large = kind == 0 ? 1.0f : 0.0f;
                    if (fy > 0.0f) splat(ry, ly * ((a + large) / (fy * m_invB + m_pLarge)));
                    if (a < 1.0f && ch.f > 0.0f)
                        splat(ch.raster, ch.radiance * ((1.0f - a) / (ch.f * m_invB + m_pLarge)));
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

        void passCompleted(const PassInfo& pass) override {
            m_perChainDone += perChain(pass);
            m_snapshot = resolve();
            m_snapshot.metadata().spp = pass.first + pass.count;
        }

        FrameBuffers snapshot() override { return m_snapshot; }

        /// The frame of the completed passes; empty before the first.
        const FrameBuffers& last() const { return m_snapshot; }
        std::uint64_t perChainDone() const { return m_perChainDone; }

      private:
        // Pixel value of a group: (pixels / M_g) Σ splats (Kelemen et al. 2002, sec. 5, with a
        // box pixel filter); the image is the mean of the group images and its variance of the
        // mean the batch-means estimate Σ (I_g − Ī)² / (K (K − 1)).
        FrameBuffers resolve() const {
            FrameBuffers frame = m_features;
            Image& color = frame.color();
            Image& variance = frame.ensure(Layer::Variance);
            const int width = frame.width();
            const std::size_t pixels = std::size_t(width) * std::size_t(frame.height());
            const double mg = double(m_perChainDone) * double(m_chains.size() / m_groups.size());
            const double scale = m_fullScale / mg;
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

        MltIntegrator& m_self;
        std::vector<Chain>& m_chains;
        std::vector<Group>& m_groups;
        const FrameBuffers& m_features;
        const std::array<float, kMutationKinds>& m_cdf;
        float m_pLarge, m_invB;
        double m_fullScale;
        std::uint64_t m_perChainDone = 0;
        FrameBuffers m_snapshot;
    };

    ChainPasses work(*this, chains, groups, features, cdf, pLarge, invB, fullScale);
    LoopResult loopResult;
    if (!chains.empty()) {
        // The time left after the bootstrap; a spent budget still counts as timed.
        const double budget = timed ? std::max(timeBudget - bootSeconds, 1e-9) : 0.0;
        RenderLoop loop(spp, budget, callbacks, arena, progressBegin, 1.0);
        loopResult = loop.run(work);
    }
    int done = loopResult.completedSpp;
    const bool cancelled = loopResult.cancelled;

    // Result: the last completed pass (a cancelled pass is not included).
    // A black image (b = 0) needs no chains: it is exactly zero for the whole budget.
    if (chains.empty() && !timed) done = spp;
    FrameBuffers result = std::move(features);
    if (work.perChainDone() == 0) {
        result.color().fill(0.0f);
        result.ensure(Layer::Variance).fill(0.0f);
    } else {
        result.set(Layer::Color, work.last().color());
        result.set(Layer::Variance, work.last().layer(Layer::Variance));
    }

    // Statistics.
    for (const Group& g : groups) {
        for (int k = 0; k < kMutationKinds; ++k)
            ms.proposed[std::size_t(k)] += g.proposed[std::size_t(k)],
                ms.accepted[std::size_t(k)] += g.accepted[std::size_t(k)];
        rays += g.rays;
        nonFinite += g.nonFinite;
    }
    ms.mutations = work.perChainDone() * std::uint64_t(chains.size());
    ms.mutationSeconds = elapsed() - bootSeconds;
    for (int k = 0; k < kMutationKinds; ++k)
        ms.probabilities[std::size_t(k)] = weight[std::size_t(k)] / weightSum;
    ms.chains = nChains;
    ms.groups = nGroups;
    ms.featureSpp = mlt.featureSpp;

    // The file records what the statistics say (strings in metadata are for files).
    FrameMetadata& meta = result.metadata();
    meta.spp = done;
    meta.integrator = integratorName(Integrator::Mlt);
    meta.nonFiniteSamples += nonFinite;
    meta.extra["mltVariance"] = "batch-means over " + std::to_string(nGroups) + " groups of " +
                                std::to_string(nChains / nGroups) + " chains";
    meta.extra["mltSampleCount"] = "feature pass";
    meta.extra["mltB"] = formatDouble(b);
    meta.extra["mltBRelStdErr"] = formatDouble(ms.bRelStdErr);
    meta.extra["mltBootstrap"] = std::to_string(nBoot);
    meta.extra["mltChains"] = std::to_string(nChains);
    meta.extra["mltMutations"] = std::to_string(ms.mutations);
    meta.extra["mltMutationsPerSecond"] = formatDouble(ms.mutationsPerSecond());
    meta.extra["mltFeatureSpp"] = std::to_string(mlt.featureSpp);
    meta.extra["mltProbabilities"] =
        formatDouble(ms.probabilities[0]) + " " + formatDouble(ms.probabilities[1]) + " " +
        formatDouble(ms.probabilities[2]) + " " + formatDouble(ms.probabilities[3]);
    for (int k = 0; k < kMutationKinds; ++k) {
        std::string name = mutationName(MutationKind(k));
        name[0] = char(std::toupper(static_cast<unsigned char>(name[0])));
        meta.extra["mltAcceptance" + name] = formatDouble(ms.acceptance(k));
    }
    if (cancelled) meta.extra["cancelled"] = "true";

    stats.seconds += elapsed();
    stats.samples += ms.mutations + ms.bootstrap;
    stats.rays += rays;
    stats.nonFiniteSamples = meta.nonFiniteSamples;
    stats.passes = loopResult.passes;
    stats.completedSpp = done;
    stats.cancelled = stats.cancelled || cancelled;
    stats.mlt = ms;
    return result;
}

}  // namespace glint::render
