// Why the denoised error does not fall where an adaptive render spends its samples
// (docs/lab/adaptive-dof-denoiser.md, "Why dof's denoised error does not fall where samples go").
// On one scene at --spp mean, with the oracle allocation of bench_adaptive_oracle (another seed's
// true error after auto, box-blurred 5×5, n_i ∝ √e_i, at least --pilot):
// Errors are against --reference (scenes/<scene>/reference.exr unless given: scene_reference.h).
//  1. Uniform at --spp against uniform at 4× --spp (same seed): in the worst 10 % of the pixels
//     by the map (and in the rest), how much the noisy, the denoised and the oracle-choice error
//     fall, and the reference's own noise (a floor no sample removes: by its variance layer, or
//     measured against --reference2, the scene rendered again at another seed).
//  2. The oracle allocation against uniform at the same samples, pixels binned by n_i / --spp:
//     per bin, the ratio of the noisy, the denoised and the oracle-choice error, against 1/n's.
//  3. The same for each auto variant (--variants, tuning overrides over balanced's): which
//     stage keeps a high-n pixel's error from falling; and each variant's whole-image relMSE,
//     oracle against uniform at equal samples and at the oracle's rays.
// The oracle choice: per pixel, the member (or the noisy input) of least 5×5-blurred true error:
// what a choice with the reference could take from the bank.
//   build/bin/bench_adaptive_denoised [--scene dof] [--seed 21] [--map-seed 1021] [--spp 1024]
//       [--pilot 64] [--threads 2] [--high 4] [--variants default,feather0,stack0]
//       [--reference scenes/dof/reference.exr] [--reference2 reference_seed8.exr]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/pipeline/refresh.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

#include "bench_options.h"
#include "oracle_allocation.h"
#include "scene_reference.h"

namespace {

using glint::bench::boxBlur;
using glint::bench::Errors;
using glint::bench::mean;
using glint::bench::relativeErrors;

/// Σ v over the pixels where `in` holds.
double sumOver(const Errors& v, const std::vector<char>& in) {
    double s = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i)
        if (in[i]) s += v[i];
    return s;
}

/// "bilateral(sigmaS=2,...)": a member in one short word list.
std::string describe(const glint::denoise::BankMember& m) {
    std::string s = m.filter + "(";
    bool first = true;
    for (const auto& [name, value] : m.params) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s%s=%.3g", first ? "" : ",", name.c_str(), value);
        s += buf;
        first = false;
    }
    return s + ")";
}

/// One frame, its bank, and auto's variants on it.
struct Analysed {
    glint::FrameBuffers frame;
    glint::render::RenderStats stats;
    Errors noisy;                            // per pixel, of the noisy image
    Errors oracleChoice;                     // per pixel, of the reference-made choice
    std::map<std::string, Errors> denoised;  // per variant, per pixel
    std::map<std::string, glint::denoise::AutoResult> results;
    glint::denoise::FilterBank bank;
};

}  // namespace

int main(int argc, char** argv) {
    std::string scene = "dof", referencePath, reference2;
    unsigned long long seed = 21, mapSeed = 1021;
    int spp = 1024, pilot = 64, threads = 2, high = 4;
    std::string variants = "default,feather0,stack0,window4,hard,shortlist0,plain";
    glint::bench::OptionTable options;
    options.bind("--scene", scene);
    options.bind("--seed", seed);
    options.bind("--map-seed", mapSeed);
    options.bind("--spp", spp);
    options.bind("--pilot", pilot);
    options.bind("--threads", threads);
    options.bind("--high", high);
    options.bind("--variants", variants);
    options.bind("--reference", referencePath);
    options.bind("--reference2", reference2);
    if (const int rc = options.parse("bench_adaptive_denoised", argc, argv)) return rc;
    // Tuning overrides over balanced's defaults, by name.
    const std::map<std::string, glint::denoise::ParamValues> known = {
        {"default", {}},
        {"feather0", {{"feather", 0.0}}},
        {"stack0", {{"stack", 0.0}}},
        {"window4", {{"window", 4.0}}},
        {"window2", {{"window", 2.0}, {"finer", 0.0}}},
        {"hard", {{"temperature", 0.0}}},
        {"shortlist0", {{"shortlist", 0.0}}},
        {"confidence0", {{"confidence", 0.0}}},
        {"plain", {{"feather", 0.0}, {"stack", 0.0}, {"window", 2.0}, {"finer", 0.0}}},
    };
    const std::vector<std::string> wanted = glint::bench::splitList(variants);
    for (const std::string& v : wanted)
        if (!known.count(v)) {
            std::fprintf(stderr, "bench_adaptive_denoised: unknown variant '%s'\n", v.c_str());
            return 2;
        }
    if (spp < 16 || pilot < 1 || pilot > spp) {
        std::fprintf(stderr, "bench_adaptive_denoised: --spp needs >= 16 and --pilot 1 … spp\n");
        return 2;
    }
    if (high < 1) {
        std::fprintf(stderr, "bench_adaptive_denoised: --high needs a factor >= 1\n");
        return 2;
    }
    const std::string dir = std::string(GLINT_SOURCE_DIR) + "/scenes/" + scene;
    glint::render::Renderer renderer(glint::render::loadScene(dir + "/scene.json"));
    const int w = renderer.scene().width(), h = renderer.scene().height();
    const std::size_t pixels = std::size_t(w) * h;
    // A reference EXR of the film's size, or one line and false.
    auto readReference = [&](const std::string& path, const char* flag, glint::FrameBuffers& out) {
        try {
            out = glint::readExr(path);
        } catch (const glint::Error& e) {
            std::fprintf(stderr, "bench_adaptive_denoised: %s: %s\n", flag, e.what());
            return false;
        }
        if (out.width() != w || out.height() != h) {
            std::fprintf(stderr, "bench_adaptive_denoised: %s: %s is %dx%d, the scene %dx%d\n",
                         path.c_str(), flag, out.width(), out.height(), w, h);
            return false;
        }
        return true;
    };
    glint::FrameBuffers referenceFrame;
    if (!readReference(referencePath.empty() ? glint::bench::sceneReference(scene) : referencePath,
                       "--reference", referenceFrame))
        return 2;
    const glint::Image& reference = referenceFrame.color();
    const glint::pipeline::AutoRun run =
        glint::pipeline::autoRun({}, glint::denoise::AutoQuality::Balanced);

    // The reference's own noise per pixel in relMSE's terms: the part of every measured error
    // that no sample removes. From its variance layer (the variance of the mean, which overstates
    // a Sobol render's error), or, with --reference2 (the same scene rendered again at another
    // seed and the same spp), measured: E[(r2 − r1)²] = 2 Var r, unbiased per pixel.
    Errors varianceFloor(pixels, 0.0), floor(pixels, 0.0);
    if (referenceFrame.has(glint::Layer::Variance)) {
        const glint::Image& v = referenceFrame.layer(glint::Layer::Variance);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                double s = 0.0;
                for (int c = 0; c < 3; ++c)
                    s += double(v(x, y, c)) /
                         (double(reference(x, y, c)) * reference(x, y, c) + 0.01);
                varianceFloor[std::size_t(y) * w + x] = s / 3.0;
            }
    }
    floor = varianceFloor;
    if (!reference2.empty()) {
        glint::FrameBuffers read;
        if (!readReference(reference2, "--reference2", read)) return 2;
        const glint::Image& second = read.color();
        const Errors twice = relativeErrors(second, reference);
        for (std::size_t i = 0; i < pixels; ++i) floor[i] = 0.5 * twice[i];
    }

    auto settingsFor = [&](unsigned long long s, int n) {
        glint::render::Settings settings = renderer.scene().settings();
        settings.seed = s;
        settings.threads = threads;
        settings.spp = n;
        settings.timeLimit = 0.0;
        settings.halfBuffers = true;
        return settings;
    };
    auto analyse = [&](glint::render::RenderResult rendered, const std::vector<std::string>& vs) {
        Analysed a;
        a.frame = std::move(rendered.frame);
        a.stats = rendered.stats;
        a.noisy = relativeErrors(a.frame.color(), reference);
        a.bank = glint::denoise::buildBank(a.frame, run.bank);
        for (const std::string& v : vs) {
            glint::denoise::AutoOptions o = run.autoOptions;
            o.tuning = known.at(v);
            glint::denoise::AutoResult r = glint::denoise::autoComposite(a.bank, a.frame, o);
            a.denoised[v] = relativeErrors(r.composite, reference);
            a.results[v] = std::move(r);
        }
        // The oracle choice: least blurred true error among the members and the noisy input.
        std::vector<Errors> errors;
        errors.push_back(a.noisy);
        for (std::size_t m = 0; m < a.bank.size(); ++m)
            errors.push_back(relativeErrors(a.bank.result(m), reference));
        a.oracleChoice.assign(pixels, 0.0);
        Errors best(pixels, 1e300);
        for (const Errors& e : errors) {
            const Errors b = boxBlur(e, w, h, 2);
            for (std::size_t i = 0; i < pixels; ++i)
                if (b[i] < best[i]) best[i] = b[i], a.oracleChoice[i] = e[i];
        }
        return a;
    };

    // The map: another seed's true error after auto, blurred; the oracle's targets from it.
    const Analysed other = analyse(renderer.render(settingsFor(mapSeed, spp)), {"default"});
    const Errors map = boxBlur(other.denoised.at("default"), w, h, 2);
    // Samples per pixel ∝ √e (at least `least`, at most 16× spp, mean spp).
    auto targetsFrom = [&](const Errors& e, int least) {
        Errors weight(pixels);
        for (std::size_t i = 0; i < pixels; ++i) weight[i] = std::sqrt(std::max(0.0, e[i]));
        return glint::bench::targetsFrom(weight, spp, least);
    };
    const std::vector<int> target = targetsFrom(map, pilot);
    std::vector<char> worst(pixels, 0), rest(pixels, 1);
    {
        std::vector<std::size_t> order(pixels);
        std::iota(order.begin(), order.end(), std::size_t(0));
        std::sort(order.begin(), order.end(), [&](auto a, auto b) { return map[a] > map[b]; });
        for (std::size_t k = 0; k < pixels / 10; ++k) worst[order[k]] = 1, rest[order[k]] = 0;
    }

    // 1. Uniform at spp and at high × spp.
    const Analysed uniform = analyse(renderer.render(settingsFor(seed, spp)), wanted);
    const Analysed uniformHigh =
        high > 1 ? analyse(renderer.render(settingsFor(seed, high * spp)), {"default"})
                 : Analysed{};
    std::printf(
        "# %s seed %llu map seed %llu, %d spp; reference floor %.3g (%.0f %% of "
        "uniform's denoised; %s), by its variance layer %.3g\n",
        scene.c_str(), seed, mapSeed, spp, mean(floor),
        100.0 * mean(floor) / mean(uniform.denoised.at("default")),
        reference2.empty() ? "its variance layer" : "measured by --reference2",
        mean(varianceFloor));
    if (high > 1) {
        std::printf(
            "pixels\tshare\tnoisy %dx\tnoisy-floor %dx\tdenoised %dx\tdenoised-floor "
            "%dx\toracleChoice %dx\tfloor/denoised\n",
            high, high, high, high, high);
        for (const auto& [name, in] :
             {std::pair{"worst10", &worst}, std::pair{"rest", &rest},
              std::pair{"all", static_cast<std::vector<char>*>(nullptr)}}) {
            std::vector<char> all(pixels, 1);
            const std::vector<char>& set = in ? *in : all;
            const double f = sumOver(floor, set);
            const double d = sumOver(uniform.denoised.at("default"), set);
            const double dh = sumOver(uniformHigh.denoised.at("default"), set);
            const double r = sumOver(uniform.noisy, set), rh = sumOver(uniformHigh.noisy, set);
            std::printf("%s\t%.3f\t%.2f\t%.2f\t%.2f\t%.2f\t%.2f\t%.3f\n", name,
                        d / sumOver(uniform.denoised.at("default"), all), r / rh,
                        (r - f) / (rh - f), d / dh, (d - f) / (dh - f),
                        sumOver(uniform.oracleChoice, set) / sumOver(uniformHigh.oracleChoice, set),
                        f / d);
        }
    }

    // 2. The oracle's render: adaptive passes that open exactly the pixels below their target.
    glint::render::RenderResult oracleRender =
        glint::bench::renderTargets(renderer, settingsFor(seed, spp), target, pilot);
    const Analysed oracle = analyse(std::move(oracleRender), wanted);
    const int equalSpp =
        int(std::lround(double(spp) * double(oracle.stats.rays) / double(uniform.stats.rays)));
    const Analysed equalRays = analyse(renderer.render(settingsFor(seed, equalSpp)), wanted);

    // Bins of n_i / spp.
    const double edges[] = {0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 1e9};
    const int bins = 6;
    const glint::Image& count = oracle.frame.layer(glint::Layer::SampleCount);
    std::vector<int> binOf(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        const double r = double(count.data()[i]) / spp;
        int b = 0;
        while (b + 1 < bins && r >= edges[b + 1]) ++b;
        binOf[i] = b;
    }
    for (const std::string& v : wanted) {
        std::printf("\n## variant %s: oracle / uniform at equal samples, per bin of n/spp\n",
                    v.c_str());
        std::printf(
            "bin\tpixels\tshareOfUniform\tmeanN/spp\tideal 1/n\tnoisy\tdenoised\t"
            "denoised-floor\toracleChoice\tfloor/uniform\ttopMembers(oracle)\n");
        for (int b = 0; b < bins; ++b) {
            std::vector<char> in(pixels, 0);
            double nsum = 0.0, ideal = 0.0, eu = 0.0;
            int k = 0;
            for (std::size_t i = 0; i < pixels; ++i)
                if (binOf[i] == b) {
                    in[i] = 1;
                    ++k;
                    nsum += count.data()[i] / double(spp);
                    ideal += uniform.denoised.at(v)[i] * spp / count.data()[i];
                    eu += uniform.denoised.at(v)[i];
                }
            if (k == 0) continue;
            const double f = sumOver(floor, in);
            const double du = sumOver(uniform.denoised.at(v), in);
            const double d = sumOver(oracle.denoised.at(v), in);
            // The members carrying most weight in the bin (of the blend auto corrected).
            std::vector<std::pair<double, int>> carried;
            for (const glint::denoise::AutoLayer& l : oracle.results.at(v).layers) {
                double s = 0.0;
                for (std::size_t i = 0; i < pixels; ++i)
                    if (in[i]) s += l.weights.data()[i];
                carried.push_back({s / k, l.member});
            }
            std::sort(carried.rbegin(), carried.rend());
            std::string top;
            for (std::size_t j = 0; j < std::min<std::size_t>(3, carried.size()); ++j) {
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.2f ", carried[j].first);
                top += std::string(j ? "; " : "") + buf +
                       describe(oracle.bank.members()[std::size_t(carried[j].second)]);
            }
            std::printf(
                "[%.2g,%.2g)\t%d\t%.3f\t%.2f\t%.2f\t%.2f\t%.2f\t%.2f\t%.2f\t%.3f\t%s\n", edges[b],
                edges[b + 1], k, eu / sumOver(uniform.denoised.at(v), std::vector<char>(pixels, 1)),
                nsum / k, ideal / eu, sumOver(oracle.noisy, in) / sumOver(uniform.noisy, in),
                d / du, (d - f) / (du - f),
                sumOver(oracle.oracleChoice, in) / sumOver(uniform.oracleChoice, in), f / du,
                top.c_str());
        }
    }
    std::printf(
        "\nvariant\tuniform\toracle\tequalRays(%d spp)\tvsEqualSamples\tvsEqualRays\t"
        "vsEqualRays-floor\toracleChoice vsEqualRays\n",
        equalSpp);
    const double fl = mean(floor);
    for (const std::string& v : wanted) {
        const double u = mean(uniform.denoised.at(v)), o = mean(oracle.denoised.at(v)),
                     e = mean(equalRays.denoised.at(v));
        std::printf("%s\t%.4g\t%.4g\t%.4g\t%+.1f %%\t%+.1f %%\t%+.1f %%\t%+.1f %%\n", v.c_str(), u,
                    o, e, 100.0 * (o / u - 1.0), 100.0 * (o / e - 1.0),
                    100.0 * ((o - fl) / (e - fl) - 1.0),
                    100.0 * (mean(oracle.oracleChoice) / mean(equalRays.oracleChoice) - 1.0));
    }
    std::printf("raw\t%.4g\t%.4g\t%.4g\n", mean(uniform.noisy), mean(oracle.noisy),
                mean(equalRays.noisy));
    std::printf("oracleChoice\t%.4g\t%.4g\t%.4g\n", mean(uniform.oracleChoice),
                mean(oracle.oracleChoice), mean(equalRays.oracleChoice));
    // What the allocation would give if every pixel's error fell as 1/n, with and without the
    // floor; and the bound of any allocation of the same samples (n_i ∝ √e_i, no pilot).
    {
        const Errors& e = uniform.denoised.at("default");
        double predicted = 0.0, predictedTrue = 0.0, rootE = 0.0, rootTrue = 0.0, trueSum = 0.0;
        for (std::size_t i = 0; i < pixels; ++i) {
            const double ratio = double(spp) / count.data()[i];
            predicted += e[i] * ratio;
            predictedTrue += (e[i] - floor[i]) * ratio + floor[i];
            rootE += std::sqrt(e[i]);
            rootTrue += std::sqrt(std::max(0.0, e[i] - floor[i]));
            trueSum += e[i] - floor[i];
        }
        const double n = double(pixels), total = mean(e) * n;
        std::printf(
            "if 1/n: this allocation %+.1f %% (%+.1f %% with the floor not falling); bound "
            "%+.1f %% (%+.1f %% of the error above the floor)\n",
            100.0 * (predicted / total - 1.0), 100.0 * (predictedTrue / total - 1.0),
            100.0 * (rootE * rootE / n / total - 1.0),
            100.0 * (rootTrue * rootTrue / n / trueSum - 1.0));
    }
    // The same prediction for other maps (nothing rendered): uniform's own error e, unblurred
    // (what the bound's allocation is, but with the pilot and the cap), and the map seed's at
    // other blurs and pilots. A map made from the very realisation it is judged on scores its
    // own noise: the bound above is of that kind.
    {
        const Errors& e = uniform.denoised.at("default");
        auto predict = [&](const std::vector<int>& t) {
            double p = 0.0, pf = 0.0;
            for (std::size_t i = 0; i < pixels; ++i) {
                p += e[i] * spp / t[i];
                pf += (e[i] - floor[i]) * spp / t[i] + floor[i];
            }
            const double total = mean(e) * double(pixels);
            return std::pair{100.0 * (p / total - 1.0), 100.0 * (pf / total - 1.0)};
        };
        std::printf("map\tblur\tpilot\tif1/n\tif1/n,floor\n");
        for (int least : {16, 64}) {
            const auto own = predict(targetsFrom(e, least));
            std::printf("own\t0\t%d\t%+.1f %%\t%+.1f %%\n", least, own.first, own.second);
            for (int r : {0, 1, 2, 4}) {
                const auto p =
                    predict(targetsFrom(boxBlur(other.denoised.at("default"), w, h, r), least));
                std::printf("mapSeed\t%d\t%d\t%+.1f %%\t%+.1f %%\n", r, least, p.first, p.second);
            }
        }
    }
    return 0;
}
