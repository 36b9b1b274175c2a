// bench_mlt: Metropolis (integrator mlt) against the path tracer (docs/metropolis.md).
//   bench_mlt reference SCENE.json --spp N --out REF.exr [--threads T] [--seed 1]
//       path-traced reference: colour, variance and sample count only, Zip-compressed
//   bench_mlt equal-time SCENE.json --reference REF.exr [--seconds 10,60] [--threads 2]
//       relMSE of PT and MLT after each time budget (and the reference's own share of it)
//   bench_mlt throughput SCENE.json [--spp N] [--threads 2] [--repeat R]
//       path samples/s against MLT mutations/s, runs interleaved, median and best
// Prints one JSON object on stdout.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace {

using glint::render::Integrator;
using glint::render::Renderer;
using glint::render::Settings;

struct Args {
    std::string mode, scene, out, reference;
    int spp = 0, threads = 2, repeat = 3;
    std::uint64_t seed = 2;  // references are rendered with seed 1: runs must not share samples
    bool seedGiven = false;
    std::vector<double> seconds = {10.0, 60.0};
};

[[noreturn]] void usage(const std::string& message) {
    std::fprintf(stderr, "bench_mlt: %s\n", message.c_str());
    std::exit(2);
}

Args parse(int argc, char** argv) {
    Args a;
    if (argc < 3) usage("usage: bench_mlt reference|equal-time|throughput SCENE.json [options]");
    a.mode = argv[1];
    a.scene = argv[2];
    for (int i = 3; i < argc; ++i) {
        const std::string k = argv[i];
        if (i + 1 >= argc) usage(k + " needs a value");
        const std::string v = argv[++i];
        try {
            if (k == "--spp")
                a.spp = std::stoi(v);
            else if (k == "--threads")
                a.threads = std::stoi(v);
            else if (k == "--repeat")
                a.repeat = std::max(1, std::stoi(v));
            else if (k == "--seed")
                a.seed = std::stoull(v), a.seedGiven = true;
            else if (k == "--out")
                a.out = v;
            else if (k == "--reference")
                a.reference = v;
            else if (k == "--seconds") {
                a.seconds.clear();
                std::stringstream ss(v);
                for (std::string t; std::getline(ss, t, ',');) a.seconds.push_back(std::stod(t));
            } else
                usage("unknown option " + k);
        } catch (const std::logic_error&) {
            usage(k + ": not a number: " + v);
        }
    }
    return a;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// relMSE that the reference's own noise adds in expectation: mean of var_ref / (r² + 0.01)
/// (the pbrt relMSE denominator of glint::relMse), over pixels and channels.
double referenceShare(const glint::FrameBuffers& ref) {
    const glint::Image* var = ref.find(glint::Layer::Variance);
    if (!var) return 0.0;
    const glint::Image& r = ref.color();
    double sum = 0.0;
    for (int y = 0; y < r.height(); ++y)
        for (int x = 0; x < r.width(); ++x)
            for (int c = 0; c < 3; ++c)
                sum += double((*var)(x, y, c)) / (double(r(x, y, c)) * r(x, y, c) + 1e-2);
    return sum / (double(r.width()) * r.height() * 3.0);
}

int run(const Args& a) {
    Renderer renderer(glint::render::loadScene(a.scene));
    Settings base = renderer.scene().settings();
    base.threads = a.threads;
    base.seed = a.seed;
    nlohmann::json j = {{"mode", a.mode}, {"scene", a.scene}, {"threads", a.threads}};

    if (a.mode == "reference") {
        if (a.out.empty() || a.spp <= 0) usage("reference needs --spp N and --out REF.exr");
        Settings s = base;
        s.spp = a.spp;
        s.seed = a.seedGiven ? a.seed : 1;
        glint::render::RenderResult result = renderer.render(s);
        glint::FrameBuffers& frame = result.frame;
        // Keep only what a reference needs, so the file stays small enough to commit.
        for (glint::Layer l :
             {glint::Layer::Albedo, glint::Layer::AlbedoVariance, glint::Layer::Normal,
              glint::Layer::NormalVariance, glint::Layer::Depth, glint::Layer::DepthVariance,
              glint::Layer::Position})
            if (frame.has(l)) frame.remove(l);
        glint::writeExr(frame, a.out, {glint::ExrCompression::Zip});
        j["spp"] = a.spp;
        j["seconds"] = result.stats.seconds;
        j["out"] = a.out;
        j["relMseShareOfReference"] = referenceShare(frame);
    } else if (a.mode == "equal-time") {
        if (a.reference.empty()) usage("equal-time needs --reference REF.exr");
        const glint::FrameBuffers ref = glint::readExr(a.reference);
        const double share = referenceShare(ref);
        j["referenceRelMseShare"] = share;
        nlohmann::json rows = nlohmann::json::array();
        for (const double sec : a.seconds) {
            nlohmann::json row = {{"seconds", sec}};
            for (const Integrator integrator : {Integrator::Path, Integrator::Mlt}) {
                Settings s = base;
                s.integrator = integrator;
                s.spp = 0;
                s.timeLimit = sec;
                const glint::render::RenderResult result = renderer.render(s);
                const glint::FrameBuffers& frame = result.frame;
                const double rel = glint::relMse(frame.color(), ref.color()).value;
                const std::string name = glint::render::integratorName(integrator);
                row[name] = {{"relMse", rel},
                             {"relMseMinusReference", rel - share},
                             {"spp", frame.metadata().spp},
                             {"secondsUsed", result.stats.seconds}};
                if (result.stats.mlt) {
                    const glint::render::MltStats& m = *result.stats.mlt;
                    row[name]["b"] = m.b;
                    row[name]["bRelStdErr"] = m.bRelStdErr;
                    row[name]["mutations"] = m.mutations;
                    row[name]["mutationsPerSecond"] = m.mutationsPerSecond();
                    for (int k = 0; k < 4; ++k)
                        row[name]["acceptance"][glint::render::mltMutationName(k)] =
                            m.acceptance(k);
                }
            }
            const double pt = row["path"]["relMseMinusReference"];
            const double mlt = row["mlt"]["relMseMinusReference"];
            row["mltOverPath"] = pt > 0.0 ? mlt / pt : 0.0;
            rows.push_back(row);
            std::fprintf(stderr, "bench_mlt: %.0f s: PT relMSE %.5g, MLT relMSE %.5g\n", sec,
                         double(row["path"]["relMse"]), double(row["mlt"]["relMse"]));
        }
        j["rows"] = rows;
    } else if (a.mode == "throughput") {
        const int spp = a.spp > 0 ? a.spp : 64;
        std::vector<double> pt, mlt;
        for (int r = 0; r < a.repeat; ++r) {
            Settings s = base;
            s.spp = spp;
            const glint::render::RenderStats path = renderer.render(s).stats;
            pt.push_back(double(path.samples) / path.seconds);
            s.integrator = Integrator::Mlt;
            mlt.push_back(renderer.render(s).stats.mlt.value().mutationsPerSecond());
        }
        j["spp"] = spp;
        j["pathSamplesPerSecondMedian"] = median(pt);
        j["pathSamplesPerSecondBest"] = *std::max_element(pt.begin(), pt.end());
        j["mltMutationsPerSecondMedian"] = median(mlt);
        j["mltMutationsPerSecondBest"] = *std::max_element(mlt.begin(), mlt.end());
        j["ratioOfMedians"] = median(mlt) / median(pt);
        j["ratioOfBest"] =
            *std::max_element(mlt.begin(), mlt.end()) / *std::max_element(pt.begin(), pt.end());
    } else {
        usage("unknown mode '" + a.mode + "' (expected reference, equal-time or throughput)");
    }
    std::cout << j.dump(2) << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const Args a = parse(argc, argv);
    try {
        return run(a);
    } catch (const glint::Error& e) {
        std::fprintf(stderr, "bench_mlt: %s\n", e.what());
        return 2;
    }
}
