// glint-report: the numbers of the speed-versus-accuracy report (docs/tradeoffs.md), computed
// with Glint's public API as an outside program would. One subcommand per part, each writing
// one CSV (to a temporary name, then renamed); tests/perf/report/run.sh runs them all and
// plot_tradeoffs.py draws the plots.
//   glint-report convergence SCENE_DIR --out F.csv [--scale 2] [--max-spp 1024] [--methods ...]
//   glint-report denoise SCENE_DIR --out F.csv [--max-spp 1024]
//   glint-report bilateral-mc SCENE_DIR --out F.csv [--scale 2] [--spp 64]
//   glint-report threads SCENE_DIR --out F.csv
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/task_arena.h>
#include <nlohmann/json.hpp>

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

double secondsSince(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// scenes/NAME/scene.json with its film divided by `scale` (the camera and everything else
/// unchanged, so each pixel covers `scale`² pixels of the full-resolution film).
render::Scene loadScaled(const fs::path& dir, int scale) {
    nlohmann::json j;
    std::ifstream(dir / "scene.json") >> j;
    j["film"]["width"] = j["film"]["width"].get<int>() / scale;
    j["film"]["height"] = j["film"]["height"].get<int>() / scale;
    return render::parseScene(j.dump(), dir / "scene.json");
}

/// The colour of dir/reference.exr averaged over scale × scale blocks: with a box pixel filter
/// this is exactly the reference of the film divided by `scale`.
Image referenceAt(const fs::path& dir, int scale) {
    const Image full = readExr(dir / "reference.exr").color();
    const int w = full.width() / scale, h = full.height() / scale;
    Image out(w, h, 3, 0.0f);
    for (int y = 0; y < h * scale; ++y)
        for (int x = 0; x < w * scale; ++x)
            for (int c = 0; c < 3; ++c)
                out(x / scale, y / scale, c) += full(x, y, c) / float(scale * scale);
    return out;
}

/// Writes `text` to `path` through a temporary name.
void writeAtomically(const fs::path& path, const std::string& text) {
    const fs::path tmp = path.string() + ".tmp";
    std::ofstream(tmp) << text;
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
/// reaches, the elapsed seconds and the relMSE and SSIM against the reference.
void convergence(const Args& a) {
    const fs::path dir = a.positional[0];
    const int scale = std::stoi(a.get("scale", "2"));
    const int maxSpp = std::stoi(a.get("max-spp", "1024"));
    const std::string methods = a.get("methods", "power,balance,none,mlt");
    const Image reference = referenceAt(dir, scale);
    std::ostringstream csv;
    csv << "scene,method,spp,seconds,relmse,ssim\n";
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
                    << ssim(rm.frame.color(), reference).value << '\n';
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
                    << ssim(frame.color(), reference).value << '\n';
            }
            excluded += secondsSince(t0);
        };
        renderer.render(s, cb);
        std::fprintf(stderr, "convergence %s %s done\n", dir.filename().c_str(), method.c_str());
    }
    writeAtomically(a.options.at("out"), csv.str());
}

// ---- part 3 and 4: denoising and the render + denoise frontier ------------------------------

/// Each filter at its defaults and at two other settings (every parameter at 25 % and 75 % of
/// its soft range, as the filter bank maps them).
std::vector<std::pair<std::string, denoise::ParamValues>> filterSettings(const denoise::Filter& f) {
    std::vector<std::pair<std::string, denoise::ParamValues>> out{{"default", {}}};
    for (double u : {0.25, 0.75}) {
        denoise::ParamValues p;
        for (const denoise::ParamSpec& spec : f.params())
            if (spec.choices.empty() && spec.name != "seed" && spec.name != "radius")
                p[spec.name] = denoise::mapParam(spec, u);
        out.push_back({u < 0.5 ? "soft25" : "soft75", p});
    }
    return out;
}

void denoiseReport(const Args& a) {
    const fs::path dir = a.positional[0];
    const int maxSpp = std::stoi(a.get("max-spp", "1024"));
    const Image reference = referenceAt(dir, 1);
    render::Renderer renderer(loadScaled(dir, 1));
    render::Settings s = renderer.scene().settings();
    s.spp = maxSpp;
    s.threads = 2;
    std::ostringstream csv;
    csv << "spp,render_seconds,filter,setting,filter_seconds,ssim_noisy,ssim\n";
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
            csv << spp << ',' << renderSeconds << ",none,none,0," << noisy << ',' << noisy << '\n';
            for (const denoise::Filter* f : denoise::allFilters())
                for (const auto& [name, params] : filterSettings(*f)) {
                    denoise::FilterOptions fo;
                    fo.threads = 2;
                    const Clock::time_point f0 = Clock::now();
                    const Image out = denoise::applyFilter(*f, frame, params, fo);
                    const double fs = secondsSince(f0);
                    csv << spp << ',' << renderSeconds << ',' << f->name() << ',' << name << ','
                        << fs << ',' << noisy << ',' << ssim(out, reference).value << '\n';
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
    const FrameBuffers frame = renderer.render(s).frame;
    const denoise::Filter& exact = denoise::findFilter("bilateral");
    const denoise::Filter& mc = denoise::findFilter("bilateral-mc");
    std::ostringstream csv;
    csv << "sigma_s,radius,pattern,k,samples,seconds,exact_seconds,psnr\n";
    denoise::FilterOptions fo;
    fo.threads = 2;
    for (double sigmaS : {5.0, 10.0, 20.0, 40.0, 80.0}) {
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

/// One workload on `threads` threads; returns seconds.
double workload(const std::string& what, const fs::path& dir, int threads) {
    render::Renderer renderer(loadScaled(dir, 1));
    render::Settings s = renderer.scene().settings();
    s.spp = 16;
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

/// Runs `glint-report peak WHAT DIR` in a child and returns its peak memory.
std::uint64_t childPeak(const char* self, const std::string& what, const fs::path& dir) {
    int fd[2];
    if (pipe(fd) != 0) throw Error(ErrorKind::Internal, "pipe failed");
    const pid_t pid = fork();
    if (pid == 0) {
        dup2(fd[1], 1);
        close(fd[0]);
        execl(self, self, "peak", what.c_str(), dir.c_str(), nullptr);
        _exit(127);
    }
    close(fd[1]);
    std::string text;
    char buf[256];
    for (ssize_t n; (n = read(fd[0], buf, sizeof buf)) > 0;) text.append(buf, std::size_t(n));
    close(fd[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    return std::stoull(text);
}

void threadsReport(const Args& a, const char* self) {
    const fs::path dir = a.positional[0];
    std::ostringstream csv;
    csv << "workload,threads,seconds,peak_bytes,megapixels,bytes_per_megapixel\n";
    const std::uint64_t baseline = childPeak(self, "none", dir);
    render::Renderer r(loadScaled(dir, 1));
    const FrameBuffers f = [&] {
        render::Settings s = r.scene().settings();
        s.spp = 1;
        return r.render(s).frame;
    }();
    const double mp = double(f.width()) * f.height() / 1e6;
    for (const std::string what : {"render", "bank", "session"}) {
        const std::uint64_t peak = childPeak(self, what, dir);
        for (int threads : {1, 2}) {
            double best = 1e30;
            for (int rep = 0; rep < 3; ++rep) best = std::min(best, workload(what, dir, threads));
            csv << what << ',' << threads << ',' << best << ',' << peak - baseline << ',' << mp
                << ',' << double(peak - baseline) / mp << '\n';
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
                         "--out F.csv [options] (docs/tradeoffs.md)\n");
            return 2;
        }
        const std::string cmd = argv[1];
        if (cmd == "peak") {
            // Child of `threads`: one workload (or none, the baseline), then its peak memory.
            const std::string what = argv[2];
            if (what != "none") workload(what, argv[3], 2);
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
