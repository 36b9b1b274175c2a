// glint-report: the numbers of the speed-versus-accuracy report (docs/lab/tradeoffs.md), computed
// with Glint's public API as an outside program would. One subcommand per part, each writing
// one CSV (to a temporary name, then renamed); lab/bench/report/run.sh runs them all and
// plot_tradeoffs.py draws the plots.
//   glint-report convergence SCENE_DIR --out F.csv [--scale 2] [--max-spp 1024] [--methods ...]
//   glint-report denoise SCENE_DIR --out F.csv [--max-spp 1024] [--bank 16]
//   glint-report bilateral-mc SCENE_DIR --out F.csv [--scale 2] [--spp 64] [--sigmas 5,...,80]
//   glint-report threads SCENE_DIR --out F.csv [--grow 4]
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

#include "bank/bank_detail.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/render/renderer.h"
#include "glint/render/scene.h"

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace glint;

namespace {

/// HDR-FLIP's mean error against the reference; NaN where it is undefined (a reference half or
/// more black, glint/image/flip.h).
double hdrFlip(const Image& image, const Image& reference) {
    try {
        return computeMetric(Metric::FlipHdr, image, reference).value;
    } catch (const Error&) {
        return std::nan("");
    }
}

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// scenes/NAME/scene.json with its film divided by `scale` (the camera and everything else
/// unchanged, so each pixel covers `scale`² pixels of the full-resolution film), or multiplied
/// by `grow` (part 6's memory per megapixel).
render::Scene loadScaled(const fs::path& dir, int scale, int grow = 1) {
    nlohmann::json j;
    std::ifstream(dir / "scene.json") >> j;
    j["film"]["width"] = j["film"]["width"].get<int>() * grow / scale;
    j["film"]["height"] = j["film"]["height"].get<int>() * grow / scale;
    return render::parseScene(j.dump(), dir / "scene.json");
}

/// A scene's reference at the report's resolution and the error its own noise adds.
struct Reference {
    Image color;         ///< reference colour averaged over scale x scale blocks
    double floor = 0.0;  ///< expected relMSE of the reference's own noise against the truth
    int spp = 0;         ///< samples per pixel of the reference (glint:spp, 0 if unknown)
};

/// dir/reference.exr averaged over scale x scale blocks: with a box pixel filter this is
/// exactly the reference of the film divided by `scale`. Its noise floor is the relMSE its
/// variance of the mean predicts: mean of Var[r] / (r^2 + 1e-2), Var of a block mean being the
/// sum of the block's variances / scale^4 (independent pixels).
Reference referenceAt(const fs::path& dir, int scale) {
    const FrameBuffers frame = readExr(dir / "reference.exr");
    const Image& full = frame.color();
    const int w = full.width() / scale, h = full.height() / scale;
    const float n = float(scale * scale);
    Reference ref;
    ref.color = Image(w, h, 3, 0.0f);
    Image variance(w, h, 3, 0.0f);
    const bool hasVariance = frame.has(Layer::Variance);
    for (int y = 0; y < h * scale; ++y)
        for (int x = 0; x < w * scale; ++x)
            for (int c = 0; c < 3; ++c) {
                ref.color(x / scale, y / scale, c) += full(x, y, c) / n;
                if (hasVariance)
                    variance(x / scale, y / scale, c) +=
                        frame.layer(Layer::Variance)(x, y, c) / (n * n);
            }
    // Step: average the predicted squared relative error over pixels and channels.
    double sum = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) {
                const double r = ref.color(x, y, c);
                sum += variance(x, y, c) / (r * r + 1e-2);
            }
    ref.floor = sum / (3.0 * w * h);
    ref.spp = frame.metadata().spp;
    return ref;
}

/// Writes `text` to `path` through a temporary name.
void writeAtomically(const fs::path& path, const std::string& text) {
    const fs::path tmp = path.string() + ".tmp";
    {
        std::ofstream out(tmp);
        out << text;
        if (!out.flush()) throw Error(ErrorKind::Io, "cannot write '" + tmp.string() + "'");
    }
    fs::rename(tmp, path);
}

bool isPowerOfTwo(int n) {
    return n > 0 && (n & (n - 1)) == 0;
}

/// Parses "--key value" options after the positional arguments.
struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> options;
    std::string get(const std::string& key, const std::string& fallback) const {
        const auto it = options.find(key);
        return it == options.end() ? fallback : it->second;
    }
};

Args parseArgs(int argc, char** argv, int first) {
    Args a;
    for (int i = first; i < argc; ++i) {
        const std::string s = argv[i];
        if (s.rfind("--", 0) == 0 && i + 1 < argc)
            a.options[s.substr(2)] = argv[++i];
        else
            a.positional.push_back(s);
    }
    if (a.positional.empty() || !a.options.count("out"))
        throw Error(ErrorKind::InvalidArgument, "expected SCENE_DIR and --out F.csv");
    return a;
}

// ---- part 1 and 2: convergence -------------------------------------------------------------

/// Renders progressively up to maxSpp and records, at every power-of-two spp the pass schedule
/// reaches, the elapsed seconds and the relMSE, SSIM and HDR-FLIP against the reference.
void convergence(const Args& a) {
    const fs::path dir = a.positional[0];
    const int scale = std::stoi(a.get("scale", "2"));
    const int maxSpp = std::stoi(a.get("max-spp", "1024"));
    const std::string methods = a.get("methods", "power,balance,none,mlt");
    const Reference ref = referenceAt(dir, scale);
    const Image& reference = ref.color;
    // Every row carries the reference's spp and noise floor (the relMSE a perfect image scores).
    std::ostringstream tail;
    tail << ',' << ref.spp << ',' << ref.floor << '\n';
    std::ostringstream csv;
    csv << "scene,method,spp,seconds,relmse,ssim,flip,reference_spp,reference_floor\n";
    std::stringstream list(methods);
    for (std::string method; std::getline(list, method, ',');) {
        render::Renderer renderer(loadScaled(dir, scale));
        render::Settings s = renderer.scene().settings();
        s.spp = maxSpp;
        s.threads = 2;
        s.seed = 1;
        if (method == "mlt") {
            s.integrator = render::Integrator::Mlt;
        } else {
            s.mis = render::parseMis(method);
            s.strategy = render::Strategy::Bsdf;
        }
        if (method == "mlt") {
            // Metropolis' passes are not sample counts: one render per spp (whole renders).
            for (int spp = 1; spp <= maxSpp; spp *= 2) {
                s.spp = spp;
                const render::RenderResult rm = renderer.render(s);
                csv << dir.filename().string() << ",mlt," << spp << ',' << rm.stats.seconds << ','
                    << relMse(rm.frame.color(), reference).value << ','
                    << ssim(rm.frame.color(), reference).value << ','
                    << hdrFlip(rm.frame.color(), reference) << tail.str();
            }
            std::fprintf(stderr, "convergence %s mlt done\n", dir.filename().c_str());
            continue;
        }
        const Clock::time_point start = Clock::now();
        double excluded = 0.0;  // seconds spent measuring, not rendering
        render::Callbacks cb;
        cb.passDone = [&](int, const FrameBuffers& frame) {
            const Clock::time_point t0 = Clock::now();
            const Image& count = frame.layer(Layer::SampleCount);
            const int spp = int(count(count.width() / 2, count.height() / 2, 0) + 0.5f);
            if (isPowerOfTwo(spp)) {
                const double seconds = std::chrono::duration<double>(t0 - start).count() - excluded;
                csv << dir.filename().string() << ',' << method << ',' << spp << ',' << seconds
                    << ',' << relMse(frame.color(), reference).value << ','
                    << ssim(frame.color(), reference).value << ','
                    << hdrFlip(frame.color(), reference) << tail.str();
            }
            excluded += secondsSince(t0);
        };
        renderer.render(s, cb);
        std::fprintf(stderr, "convergence %s %s done\n", dir.filename().c_str(), method.c_str());
    }
    writeAtomically(a.options.at("out"), csv.str());
}

// ---- part 3 and 4: denoising and the render + denoise frontier ------------------------------

/// Each filter at its defaults and at two other settings: every numeric parameter but the seed
/// at 25 % and 75 % of its soft range, mapped as the filter bank maps them (choices keep their
/// defaults).
std::vector<std::pair<std::string, denoise::ParamValues>> filterSettings(const denoise::Filter& f) {
    std::vector<std::pair<std::string, denoise::ParamValues>> out{{"default", {}}};
    for (double u : {0.25, 0.75}) {
        denoise::ParamValues p;
        for (const denoise::ParamSpec& spec : f.params())
            if (spec.choices.empty() && spec.name != "seed")
                p[spec.name] = denoise::detail::mapParam(spec, u);
        out.push_back({u < 0.5 ? "soft25" : "soft75", p});
    }
    return out;
}

/// The parameters a filter runs with (given values over its defaults) as "k=v k=v", for the CSV.
std::string describeParams(const denoise::Filter& f, const denoise::ParamValues& given) {
    std::ostringstream out;
    for (const denoise::ParamSpec& spec : f.params()) {
        const auto it = given.find(spec.name);
        const double v = it == given.end() ? spec.defaultValue : it->second;
        if (out.tellp() > 0) out << ' ';
        out << spec.name << '=';
        if (spec.isChoice())
            out << spec.choices[std::size_t(v)];
        else
            out << v;
    }
    return out.str();
}

void denoiseReport(const Args& a) {
    const fs::path dir = a.positional[0];
    const int maxSpp = std::stoi(a.get("max-spp", "1024"));
    const int bankSize = std::stoi(a.get("bank", "16"));
    const Image reference = referenceAt(dir, 1).color;
    render::Renderer renderer(loadScaled(dir, 1));
    render::Settings s = renderer.scene().settings();
    s.spp = maxSpp;
    s.threads = 2;
    s.seed = 1;
    // The candidates: each filter at three settings (part 3), then the members of a filter
    // bank as the studio builds it (Latin hypercube, seed 1; part 4 chooses among all rows).
    std::vector<std::tuple<const denoise::Filter*, std::string, denoise::ParamValues>> candidates;
    // Every filter that runs as it is (external needs a program the user allowed).
    std::vector<const denoise::Filter*> filters;
    for (const denoise::Filter* f : denoise::allFilters())
        if (f->unavailable(denoise::resolveParams(*f, {})).empty()) filters.push_back(f);
    for (const denoise::Filter* f : filters)
        for (auto& [name, params] : filterSettings(*f)) candidates.emplace_back(f, name, params);
    if (bankSize > 0) {
        const std::vector<denoise::BankMember> members =
            denoise::detail::sampleBank(filters, bankSize, 1);
        int i = 0;
        for (const denoise::BankMember& m : members)
            if (!m.isDefault)
                candidates.emplace_back(&denoise::findFilter(m.filter),
                                        "bank" + std::to_string(i++), m.params);
    }
    std::ostringstream csv;
    csv << "spp,render_seconds,filter,setting,filter_seconds,ssim_noisy,ssim,params\n";
    const Clock::time_point start = Clock::now();
    double excluded = 0.0;
    render::Callbacks cb;
    cb.passDone = [&](int, const FrameBuffers& frame) {
        const Clock::time_point t0 = Clock::now();
        const Image& count = frame.layer(Layer::SampleCount);
        const int spp = int(count(0, 0, 0) + 0.5f);
        if (isPowerOfTwo(spp)) {
            const double renderSeconds =
                std::chrono::duration<double>(t0 - start).count() - excluded;
            const double noisy = ssim(frame.color(), reference).value;
            csv << spp << ',' << renderSeconds << ",none,none,0," << noisy << ',' << noisy << ",\n";
            for (const auto& [f, name, params] : candidates) {
                denoise::FilterOptions fo;
                fo.threads = 2;
                const Clock::time_point f0 = Clock::now();
                const Image out = denoise::applyFilter(*f, frame, params, fo);
                const double fs = secondsSince(f0);
                csv << spp << ',' << renderSeconds << ',' << f->name() << ',' << name << ',' << fs
                    << ',' << noisy << ',' << ssim(out, reference).value << ','
                    << describeParams(*f, params) << '\n';
            }
            std::fprintf(stderr, "denoise %d spp done\n", spp);
        }
        excluded += secondsSince(t0);
    };
    renderer.render(s, cb);
    writeAtomically(a.options.at("out"), csv.str());
}

// ---- part 5: bilateral-mc against the exact filter -----------------------------------------

void bilateralMc(const Args& a) {
    const fs::path dir = a.positional[0];
    const int scale = std::stoi(a.get("scale", "2"));
    render::Renderer renderer(loadScaled(dir, scale));
    render::Settings s = renderer.scene().settings();
    s.spp = std::stoi(a.get("spp", "64"));
    s.threads = 2;
    s.seed = 1;
    const FrameBuffers frame = renderer.render(s).frame;
    const denoise::Filter& exact = denoise::findFilter("bilateral");
    const denoise::Filter& mc = denoise::findFilter("bilateral-mc");
    std::ostringstream csv;
    csv << "sigma_s,radius,pattern,k,samples,seconds,exact_seconds,psnr\n";
    denoise::FilterOptions fo;
    fo.threads = 2;
    std::vector<double> sigmas;
    std::stringstream list(a.get("sigmas", "5,10,20,40,80"));
    for (std::string item; std::getline(list, item, ',');) sigmas.push_back(std::stod(item));
    for (double sigmaS : sigmas) {
        const int radius = std::min(100, int(std::ceil(3.0 * sigmaS)));
        const denoise::ParamValues base{{"sigmaS", sigmaS}, {"sigmaR", 0.1}, {"radius", radius}};
        Clock::time_point t0 = Clock::now();
        const Image reference = denoise::applyFilter(exact, frame, base, fo);
        const double exactSeconds = secondsSince(t0);
        for (int pattern = 0; pattern < 4; ++pattern)
            for (int k = 1; k <= 7; ++k) {
                denoise::ParamValues p = base;
                p["samplesPerSide"] = k;
                p["pattern"] = pattern;
                t0 = Clock::now();
                const Image out = denoise::applyFilter(mc, frame, p, fo);
                const double seconds = secondsSince(t0);
                const char* names[] = {"poisson", "regular", "random", "stratified"};
                csv << sigmaS << ',' << radius << ',' << names[pattern] << ',' << k << ','
                    << k * (2 * radius + 1) << ',' << seconds << ',' << exactSeconds << ','
                    << psnr(out, reference).value << '\n';
            }
        std::fprintf(stderr, "bilateral-mc sigma %g done\n", sigmaS);
    }
    writeAtomically(a.options.at("out"), csv.str());
}

// ---- part 6: threads and peak memory --------------------------------------------------------

/// Peak resident memory (VmHWM) of this process in bytes.
std::uint64_t peakMemory() {
    std::ifstream in("/proc/self/status");
    std::string key;
    std::uint64_t kib = 0;
    while (in >> key)
        if (key == "VmHWM:" && (in >> kib)) break;
    return kib * 1024;
}

/// One workload on `threads` threads with the film `grow` times the scene's; returns seconds.
/// The render is 16 spp (`spp` overrides it: memory does not depend on spp); the bank (16 Latin
/// hypercube members plus each filter's defaults) and the session (two painted layers) run on a
/// 16-spp render made beforehand on 2 threads and not timed.
double workload(const std::string& what, const fs::path& dir, int threads, int grow = 1,
                int spp = 16) {
    render::Renderer renderer(loadScaled(dir, 1, grow));
    render::Settings s = renderer.scene().settings();
    s.spp = spp;
    s.seed = 1;
    s.threads = threads;
    if (what == "render") return renderer.render(s).stats.seconds;
    s.threads = 2;
    const FrameBuffers frame = renderer.render(s).frame;
    tbb::task_arena arena(threads);
    double seconds = 0.0;
    arena.execute([&] {
        const Clock::time_point t0 = Clock::now();
        if (what == "bank") {
            denoise::BankOptions o;
            o.size = 16;
            o.seed = 1;
            denoise::buildBank(frame, o);
        } else if (what == "session") {
            denoise::Session session(frame);
            session.addLayer("cross-bilateral", {});
            session.addLayer("nlmeans", {});
        }
        seconds = secondsSince(t0);
    });
    return seconds;
}

/// Runs `glint-report peak WHAT DIR GROW` in a fresh child process and returns its peak
/// resident memory (VmHWM, which a child cannot inherit from this process).
std::uint64_t childPeak(const char* self, const std::string& what, const fs::path& dir, int grow) {
    int fd[2];
    if (pipe(fd) != 0) throw Error(ErrorKind::Internal, "pipe failed");
    const std::string growText = std::to_string(grow);
    const pid_t pid = fork();
    if (pid == 0) {
        dup2(fd[1], 1);
        close(fd[0]);
        execl(self, self, "peak", what.c_str(), dir.c_str(), growText.c_str(), nullptr);
        _exit(127);
    }
    close(fd[1]);
    std::string text;
    char buf[256];
    for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, std::size_t(n));
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || text.empty())
        throw Error(ErrorKind::Internal, "peak-memory child for '" + what + "' failed");
    return std::stoull(text);
}

/// Part 6: the best of three runs on 1 and 2 threads of each workload at the scene's film, and
/// its peak memory in fresh processes at the scene's film and at 4 x 4 times it; the difference
/// divided by the megapixels added is the memory a megapixel costs (fixed costs such as the
/// BVH, thread stacks and code cancel out).
void threadsReport(const Args& a, const char* self) {
    const fs::path dir = a.positional[0];
    const int grow = std::stoi(a.get("grow", "4"));
    std::ostringstream csv;
    csv << "workload,threads,seconds,megapixels_small,peak_bytes_small,megapixels_large,"
           "peak_bytes_large,bytes_per_megapixel\n";
    const std::uint64_t baseline = childPeak(self, "none", dir, 1);
    const render::Scene scene = loadScaled(dir, 1);
    const double mpSmall = double(scene.width()) * scene.height() / 1e6;
    const double mpLarge = mpSmall * grow * grow;
    for (const std::string what : {"render", "bank", "session"}) {
        const std::uint64_t small = childPeak(self, what, dir, 1) - baseline;
        const std::uint64_t large = childPeak(self, what, dir, grow) - baseline;
        const double perMp = (double(large) - double(small)) / (mpLarge - mpSmall);
        for (int threads : {1, 2}) {
            double best = 1e30;
            for (int rep = 0; rep < 3; ++rep) best = std::min(best, workload(what, dir, threads));
            csv << what << ',' << threads << ',' << best << ',' << mpSmall << ',' << small << ','
                << mpLarge << ',' << large << ',' << perMp << '\n';
        }
        std::fprintf(stderr, "threads %s done\n", what.c_str());
    }
    writeAtomically(a.options.at("out"), csv.str());
}

}  // namespace

int main(int argc, char** argv) {
    try {
        if (argc < 3) {
            std::fprintf(stderr,
                         "usage: glint-report convergence|denoise|bilateral-mc|threads SCENE_DIR "
                         "--out F.csv [options] (docs/lab/tradeoffs.md)\n");
            return 2;
        }
        const std::string cmd = argv[1];
        if (cmd == "peak") {
            // Child of `threads`: one workload (or none, the baseline), then its peak memory.
            const std::string what = argv[2];
            if (what != "none") workload(what, argv[3], 2, argc > 4 ? std::stoi(argv[4]) : 1, 1);
            std::printf("%llu\n", (unsigned long long)peakMemory());
            return 0;
        }
        const Args a = parseArgs(argc, argv, 2);
        if (cmd == "convergence")
            convergence(a);
        else if (cmd == "denoise")
            denoiseReport(a);
        else if (cmd == "bilateral-mc")
            bilateralMc(a);
        else if (cmd == "threads")
            threadsReport(a, argv[0]);
        else
            throw Error(ErrorKind::InvalidArgument, "unknown part '" + cmd + "'");
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "glint-report: %s\n", e.what());
        return 2;
    }
}
