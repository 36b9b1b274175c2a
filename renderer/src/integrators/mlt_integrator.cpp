#include "integrators/mlt_integrator.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "glint/image/error.h"
#include "integrators/mlt_passes.h"

namespace glint::render {

namespace {

using Clock = std::chrono::steady_clock;

std::string formatDouble(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

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
    const Clock::time_point start = Clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

    MltPassSettings ps;
    ps.seed = m_settings.seed;
    ps.bootstrap = mlt.bootstrap;
    ps.chains = mlt.chains;
    ps.groups = mlt.groups;
    ps.sizes.small = {float(mlt.s1), float(mlt.s2)};
    ps.sizes.lensX = {float(mlt.lensS1 / width), float(mlt.lensS2 / width)};
    ps.sizes.lensY = {float(mlt.lensS1 / height), float(mlt.lensS2 / height)};
    ps.sizes.light = {float(mlt.lightS1), float(mlt.lightS2)};

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
    double acc = 0.0;
    for (int k = 0; k < kMutationKinds; ++k) ps.cdf[k] = float((acc += weight[k]) / weightSum);
    ps.cdf[kMutationKinds - 1] = 2.0f;  // uniform() < 1 always lands somewhere
    ps.pLarge = float(weight[0] / weightSum);

    // The bootstrap, then the chains' passes, through the shared RenderLoop
    // (integrators/mlt_passes.h): both report progress and stop when cancelled.
    const bool timed = timeBudget > 0.0;
    const int spp = m_settings.spp;
    MltPasses work(*this, width, height, ps, features);
    RenderLoop loop(spp, timeBudget, callbacks, arena, progressBegin, 1.0);
    const LoopResult loopResult = loop.run(work);
    int done = loopResult.completedSpp;
    const bool cancelled = loopResult.cancelled;

    // Result: the last completed pass (a cancelled pass is not included).
    // A black image (b = 0) needs no chains: it is exactly zero for the whole budget.
    if (work.bootstrapDone() && work.chainsStarted() == 0 && !timed) done = spp;
    FrameBuffers result = std::move(features);
    if (work.perChainDone() == 0) {
        result.color().fill(0.0f);
        result.ensure(Layer::Variance).fill(0.0f);
    } else {
        result.set(Layer::Color, work.last().color());
        result.set(Layer::Variance, work.last().layer(Layer::Variance));
    }

    // Statistics.
    MltStats ms;
    std::uint64_t rays = 0;
    std::int64_t nonFinite = 0;
    work.addStatistics(ms, rays, nonFinite);
    ms.mutationSeconds = work.bootstrapDone() ? elapsed() - work.bootstrapSeconds() : 0.0;
    for (int k = 0; k < kMutationKinds; ++k)
        ms.probabilities[std::size_t(k)] = weight[std::size_t(k)] / weightSum;
    ms.chains = mlt.chains;
    ms.groups = mlt.groups;
    ms.featureSpp = mlt.featureSpp;
    // The image's mean is b times the chains' estimate given b: their independent relative errors
    // add in quadrature (docs/metropolis.md, "Error of the image's mean").
    ms.chainsRelStdErr = work.chainsRelStdErr();
    ms.meanRelStdErr =
        std::sqrt(ms.bRelStdErr * ms.bRelStdErr + ms.chainsRelStdErr * ms.chainsRelStdErr);

    // The file records what the statistics say (strings in metadata are for files).
    FrameMetadata& meta = result.metadata();
    meta.spp = done;
    meta.integrator = integratorName(Integrator::Mlt);
    meta.nonFiniteSamples += nonFinite;
    meta.extra["mltVariance"] = "batch-means over " + std::to_string(mlt.groups) + " groups of " +
                                std::to_string(mlt.chains / mlt.groups) + " chains";
    meta.extra["mltSampleCount"] = "feature pass";
    meta.extra["mltB"] = formatDouble(ms.b);
    meta.extra["mltBRelStdErr"] = formatDouble(ms.bRelStdErr);
    meta.extra["mltChainsRelStdErr"] = formatDouble(ms.chainsRelStdErr);
    meta.extra["mltMeanRelStdErr"] = formatDouble(ms.meanRelStdErr);
    meta.extra["mltBootstrap"] = std::to_string(ms.bootstrap);
    meta.extra["mltChains"] = std::to_string(mlt.chains);
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
