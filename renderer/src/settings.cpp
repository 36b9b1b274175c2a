#include "glint/render/settings.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "glint/image/error.h"

namespace glint::render {

Integrator parseIntegrator(const std::string& name) {
    if (name == "path") return Integrator::Path;
    if (name == "mlt") return Integrator::Mlt;
    throw Error(ErrorKind::InvalidArgument,
                "unknown integrator '" + name + "' (expected path or mlt)");
}

MisHeuristic parseMis(const std::string& name) {
    if (name == "power") return MisHeuristic::Power;
    if (name == "balance") return MisHeuristic::Balance;
    if (name == "none") return MisHeuristic::None;
    throw Error(ErrorKind::InvalidArgument,
                "unknown MIS heuristic '" + name + "' (expected power, balance or none)");
}

Strategy parseStrategy(const std::string& name) {
    if (name == "bsdf") return Strategy::Bsdf;
    if (name == "light") return Strategy::Light;
    throw Error(ErrorKind::InvalidArgument,
                "unknown strategy '" + name + "' (expected bsdf or light)");
}

SamplerKind parseSampler(const std::string& name) {
    if (name == "stratified") return SamplerKind::Stratified;
    if (name == "independent") return SamplerKind::Independent;
    if (name == "sobol") return SamplerKind::Sobol;
    if (name == "zsobol") return SamplerKind::ZSobol;
    throw Error(
        ErrorKind::InvalidArgument,
        "unknown sampler '" + name + "' (expected stratified, independent, sobol or zsobol)");
}

Accel parseAccel(const std::string& name) {
    if (name == "auto") return Accel::Auto;
    if (name == "triangles") return Accel::Triangles;
    if (name == "clusters") return Accel::Clusters;
    throw Error(ErrorKind::InvalidArgument,
                "unknown accel '" + name + "' (expected auto, triangles or clusters)");
}

AdaptiveError parseAdaptiveError(const std::string& name) {
    if (name == "half") return AdaptiveError::Half;
    if (name == "whole") return AdaptiveError::Whole;
    throw Error(ErrorKind::InvalidArgument,
                "unknown adaptive error source '" + name + "' (expected half or whole)");
}

const char* adaptiveErrorName(AdaptiveError from) {
    return from == AdaptiveError::Half ? "half" : "whole";
}

int adaptiveStartSpp(const Settings& s) {
    // Cycles' automatic minimum: 32 at a threshold of 0.1, 64 at 0.01, 128 at 0.001.
    const int start =
        s.minSpp > 0
            ? s.minSpp
            : std::max(4, int(std::ceil(16.0 / std::pow(std::max(s.noiseThreshold, 1e-30), 0.3))));
    return s.spp > 0 ? std::min(start, s.spp) : std::min(start, kMaxSpp);
}

const char* accelName(Accel accel) {
    switch (accel) {
        case Accel::Auto:
            return "auto";
        case Accel::Triangles:
            return "triangles";
        case Accel::Clusters:
            return "clusters";
    }
    return "?";
}

const char* samplerName(SamplerKind sampler) {
    switch (sampler) {
        case SamplerKind::Stratified:
            return "stratified";
        case SamplerKind::Independent:
            return "independent";
        case SamplerKind::Sobol:
            return "sobol";
        case SamplerKind::ZSobol:
            return "zsobol";
    }
    return "?";
}

const char* integratorName(Integrator integrator) {
    return integrator == Integrator::Path ? "path" : "mlt";
}

const char* misName(MisHeuristic mis) {
    switch (mis) {
        case MisHeuristic::Power:
            return "power";
        case MisHeuristic::Balance:
            return "balance";
        case MisHeuristic::None:
            return "none";
    }
    return "?";
}

const char* strategyName(Strategy strategy) {
    return strategy == Strategy::Bsdf ? "bsdf" : "light";
}

namespace {

/// The adaptive-sampling part of validate().
void validateAdaptive(const Settings& s) {
    auto bad = [](const char* field, const std::string& what) {
        throw Error(ErrorKind::InvalidArgument, what, {}, field);
    };
    if (s.importance && !s.adaptive)
        bad("importance",
            "an importance map steers adaptive sampling: it needs adaptive sampling on");
    if (s.continueFrom && !s.adaptive)
        bad("continueFrom",
            "going on from a finished render adds adaptive passes: it needs adaptive sampling on");
    if (s.continueFrom && s.region)
        bad("continueFrom", "going on from a finished render takes the whole film, not a region");
    if (s.continueFrom && s.sampler == SamplerKind::ZSobol)
        bad("continueFrom",
            "the zsobol sampler lays each pixel's samples out by the render's spp, so a render "
            "cannot go on from another's (use the sobol sampler)");
    if (!(s.noiseThreshold > 0.0 && s.noiseThreshold <= kMaxNoiseThreshold)) {
        std::ostringstream got;
        got << s.noiseThreshold;
        bad("noiseThreshold",
            "noiseThreshold must be a number in (0, 1e6] (a pixel's estimated relative error; "
            "Cycles' default is 0.01), got " +
                got.str());
    }
    if (s.minSpp < 0 || s.minSpp > kMaxSpp)
        bad("minSpp", "minSpp must be in [0, " + std::to_string(kMaxSpp) +
                          "] (0: automatic), got " + std::to_string(s.minSpp));
    if (s.spp > 0 && s.minSpp > s.spp)
        bad("spp", "spp (" + std::to_string(s.spp) +
                       ", the most samples an adaptive render gives a pixel) is below minSpp (" +
                       std::to_string(s.minSpp) + ", the samples every pixel takes first)");
    if (s.integrator != Integrator::Path)
        bad("adaptive",
            "adaptive sampling works with the path integrator only (Metropolis distributes its "
            "samples by the image's brightness already)");
    if (s.sampler == SamplerKind::Stratified)
        bad("adaptive",
            "adaptive sampling needs the sobol, zsobol or independent sampler (a stratified pass "
            "stratifies over every pixel's samples of the pass, which adaptive passes split)");
    if (s.shard)
        bad("shard",
            "adaptive sampling decides per pixel from all the samples so far, which one shard "
            "does not have: render adaptively on one machine");
}

}  // namespace

void validate(const Settings& s) {
    // `where` names the field, so a command line can name its flag.
    auto bad = [](const char* field, const std::string& what) {
        throw Error(ErrorKind::InvalidArgument, what, {}, field);
    };
    auto range = [&](const char* field, long long v, long long lo, long long hi) {
        if (v < lo || v > hi)
            bad(field, std::string(field) + " must be in [" + std::to_string(lo) + ", " +
                           std::to_string(hi) + "], got " + std::to_string(v));
    };
    if (s.spp < 0 || s.spp > kMaxSpp || (s.spp == 0 && !(s.timeLimit > 0.0)))
        bad("spp", "spp must be in [1, " + std::to_string(kMaxSpp) + "] (or 0 with a time limit)");
    range("threads", s.threads, 0, kMaxThreads);
    range("maxDepth", s.maxDepth, 1, kMaxDepth);
    range("rrDepth", s.rrDepth, 0, kMaxDepth);
    if (!(s.timeLimit >= 0.0 && s.timeLimit <= kMaxTimeLimit))
        bad("timeLimit",
            "timeLimit must be a number of seconds in [0, 1e7], got " + numberText(s.timeLimit));
    if (s.seed > kMaxSeed)
        bad("seed", "seed must be in [0, 2^63 - 1], got " + std::to_string(s.seed));
    range("tileSize", s.tileSize, 1, 4096);
    range("textureCacheMb", s.textureCacheMb, 1, kMaxTextureCacheMb);
    if (s.region && s.region->empty()) bad("region", "the render region is empty");
    if (s.region && s.integrator == Integrator::Mlt)
        bad("region", "a render region works with the path integrator only");
    if (s.halfBuffers && s.integrator != Integrator::Path)
        bad("halfBuffers",
            "half buffers work with the path integrator only (Metropolis samples are not "
            "independent)");
    if (s.halfBuffers && s.sampler == SamplerKind::Stratified)
        bad("halfBuffers",
            "half buffers need the sobol or independent sampler (a stratified pass's strata span "
            "both halves, so the halves would not be independent)");
    if (s.sampler == SamplerKind::ZSobol && s.timeLimit > 0.0)
        bad("sampler",
            "the zsobol sampler needs a fixed spp (no time limit): it lays each pixel's samples "
            "out as a block of 2^ceil(log2 spp) indices");
    if (s.adaptive || s.importance || s.continueFrom) validateAdaptive(s);
    if (s.shard) {
        // The time limit first: with it spp is open (0), and the spp bound would mislead.
        if (s.timeLimit > 0.0)
            bad("shard", "a shard needs a fixed spp (no time limit): shards split the samples");
        if (s.shard->count < 1 || s.shard->count > std::max(s.spp, 1))
            bad("shard", "the number of shards must be in [1, spp = " + std::to_string(s.spp) +
                             "], got " + std::to_string(s.shard->count));
        if (s.shard->index < 0 || s.shard->index >= s.shard->count)
            bad("shard", "shard index must be in [0, " + std::to_string(s.shard->count - 1) +
                             "], got " + std::to_string(s.shard->index));
        if (s.integrator != Integrator::Path)
            bad("shard",
                "sharding works with the path integrator only (Metropolis chains are "
                "not indexed by sample)");
    }
}

}  // namespace glint::render
