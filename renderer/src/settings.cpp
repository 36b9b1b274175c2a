#include "glint/render/settings.h"

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
    throw Error(ErrorKind::InvalidArgument,
                "unknown sampler '" + name + "' (expected stratified or independent)");
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

void validate(const Settings& s) {
    // `where` names the field, so a command line can name its flag.
    auto bad = [](const char* field, const std::string& what) {
        throw Error(ErrorKind::InvalidArgument, what, {}, field);
    };
    if (s.spp < 0) bad("spp", "spp must be positive, got " + std::to_string(s.spp));
    if (s.spp == 0 && !(s.timeLimit > 0.0))
        bad("spp", "spp must be positive (or 0 with a time limit)");
    if (s.threads < 0) bad("threads", "threads must be >= 0, got " + std::to_string(s.threads));
    if (s.maxDepth < 1) bad("maxDepth", "maxDepth must be >= 1, got " + std::to_string(s.maxDepth));
    if (s.rrDepth < 0) bad("rrDepth", "rrDepth must be >= 0, got " + std::to_string(s.rrDepth));
    if (!(s.timeLimit >= 0.0)) bad("timeLimit", "timeLimit must be >= 0");
    if (s.tileSize < 1 || s.tileSize > 4096) bad("tileSize", "tileSize must be in [1, 4096]");
}

}  // namespace glint::render
