// unet — Open Image Denoise's RT filter: its U-Net with OIDN's trained weights, run on the CPU.
//
// The colour is scaled by OIDN's autoexposure (computed over the whole frame) and encoded with
// the PU transfer function; albedo is clamped to [0, 1] and normals are mapped from [-1, 1] to
// [0, 1]; NaN inputs read as 0. The network (Ronneberger et al. 2015's U-Net as trained by OIDN:
// five 2×2 max-pool levels down, nearest upsampling and skip concatenations up, 3×3 convolutions
// with ReLU) runs in fp32 with oneDNN on tiles zero-padded to a multiple of 16; the output is
// decoded by the inverse transfer and exposure. Large frames are split into tiles that overlap by
// the receptive-field half-width (96 px; 112 for the large weights), so that a tile's output
// equals a single pass; the tile size follows a memory budget.
//
// Weights (Apache-2.0, third_party_notes/oidn-weights.md) are read from the folder in
// GLINT_UNET_WEIGHTS_DIR, else the installed share/glint/weights/oidn, else the source tree's
// denoise/weights/oidn/, and checked by SHA-256; missing or corrupt weights make
// the filter unavailable (one line naming the file and the expected digest): apply() refuses to
// run and the default bank goes on without it.
//
// Parameters:
//   features  auto: colour, + albedo, + albedo + normal as the frame has them; or one set
//             (its layers must exist).
//   aux       noisy: albedo and normal straight from the render; clean: they are noise-free
//             (after --prefilter), which picks OIDN's clean-aux weights (albedo + normal only);
//             auto (the default): clean when the frame's features were prefiltered, else noisy.
//   quality   fast: the small weights; balanced: the default weights; high: the large weights
//             where OIDN has them (clean albedo + normal), else the default.
//   memoryMB  budget of the network's activations; larger frames are tiled (same output).
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "filters/factories.h"
#include "filters/filter_util.h"
#include "glint/denoise/prefilter.h"
#include "glint/image/error.h"
#include "learned/oidn_color.h"
#include "learned/sha256.h"
#include "learned/tza.h"
#include "learned/unet_network.h"
#include "learned/unet_tiles.h"
#include "learned/weights_dir.h"

namespace glint::denoise {

namespace {

using learned::UNetNetwork;

// The opening block of this file, verbatim (glint-denoise list prints it).
constexpr std::string_view kDescription =
    R"(unet — Open Image Denoise's RT filter: its U-Net with OIDN's trained weights, run on the CPU.

The colour is scaled by OIDN's autoexposure (computed over the whole frame) and encoded with
the PU transfer function; albedo is clamped to [0, 1] and normals are mapped from [-1, 1] to
[0, 1]; NaN inputs read as 0. The network (Ronneberger et al. 2015's U-Net as trained by OIDN:
five 2×2 max-pool levels down, nearest upsampling and skip concatenations up, 3×3 convolutions
with ReLU) runs in fp32 with oneDNN on tiles zero-padded to a multiple of 16; the output is
decoded by the inverse transfer and exposure. Large frames are split into tiles that overlap by
the receptive-field half-width (96 px; 112 for the large weights), so that a tile's output
equals a single pass; the tile size follows a memory budget.

Weights (Apache-2.0, third_party_notes/oidn-weights.md) are read from the folder in
GLINT_UNET_WEIGHTS_DIR, else the installed share/glint/weights/oidn, else the source tree's
denoise/weights/oidn/, and checked by SHA-256; missing or corrupt weights make
the filter unavailable (one line naming the file and the expected digest): apply() refuses to
run and the default bank goes on without it.

Parameters:
  features  auto: colour, + albedo, + albedo + normal as the frame has them; or one set
            (its layers must exist).
  aux       noisy: albedo and normal straight from the render; clean: they are noise-free
            (after --prefilter), which picks OIDN's clean-aux weights (albedo + normal only);
            auto (the default): clean when the frame's features were prefiltered, else noisy.
  quality   fast: the small weights; balanced: the default weights; high: the large weights
            where OIDN has them (clean albedo + normal), else the default.
  memoryMB  budget of the network's activations; larger frames are tiled (same output).)";

enum class Features : int { Auto = 0, Color = 1, Albedo = 2, AlbedoNormal = 3 };
enum class Quality : int { Fast = 0, Balanced = 1, High = 2 };
enum class Aux : int { Noisy = 0, Clean = 1, Auto = 2 };

// The weight files Glint ships (OIDN weights @28883d1) and their SHA-256.
struct WeightsFile {
    std::string_view name, sha256;
};
constexpr WeightsFile kWeights[] = {
    {"rt_hdr", "a097e8fe9b1ba71ec43cde3e6df3fcf54fa4f8f2f4dd41eac01d0a76a16261e3"},
    {"rt_hdr_small", "c9171947f2bceb4367725b7a0d5b4e0d663ac44108386af42f1b49e4361952e7"},
    {"rt_hdr_alb", "a8e4fbbd3a794e0098f88e23882faf5459840bda5b0ff39f22bcaaf2cfd03b5a"},
    {"rt_hdr_alb_small", "1f3839dfc949e969bc5ad4d600e85bfa96187e0cb5ffee2f4715c791e6221fba"},
    {"rt_hdr_alb_nrm", "e586ef2ff48d7fbb7611986405220ed8fc5c13ca79bfc40be4dc742fbf959e1a"},
    {"rt_hdr_alb_nrm_small", "980ea307e7825cae23ed8b1addf8de62ece84b61094795a5631ebf1c91b2e1a7"},
    {"rt_hdr_calb_cnrm", "d0057057bd76c64e3e67b449728ef8f4fd2f11ccfb74c1e59b9d50dafd50ee0e"},
    {"rt_hdr_calb_cnrm_small", "a6c43bfdbff01bdd8a9c777e139720f9e58b872a50c8db07079bddd007482dc5"},
    {"rt_hdr_calb_cnrm_large", "08130cdc4f33b7a513d0073757f089ac830f900613bb5bad72ca42c52b934465"},
};

const WeightsFile* findWeights(std::string_view name) {
    for (const WeightsFile& w : kWeights)
        if (w.name == name) return &w;
    return nullptr;
}

// The weights for a feature set, aux kind and quality (OIDN RTFilter's model table, HDR).
std::string weightsName(Features f, bool cleanAux, Quality q) {
    std::string base = "rt_hdr";
    if (f == Features::Albedo) base += "_alb";
    if (f == Features::AlbedoNormal) base += cleanAux ? "_calb_cnrm" : "_alb_nrm";
    const std::string suffix = q == Quality::Fast ? "_small" : q == Quality::High ? "_large" : "";
    return !suffix.empty() && findWeights(base + suffix) ? base + suffix : base;
}

std::vector<std::uint8_t> readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return {};
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string weightsPath(const std::string& name) {
    return (learned::weightsDir() / (name + ".tza")).string();
}

// The bytes of weight file `name` at `path`, checked against its digest: throws Error(Io) when
// missing, Error(Format) when altered, with one line naming the file and the expected digest.
std::vector<std::uint8_t> checkedWeights(const std::string& name, const std::string& path) {
    const WeightsFile* known = findWeights(name);
    GLINT_CHECK(known != nullptr, "unknown weights");
    std::vector<std::uint8_t> blob = readFile(path);
    const std::string expected = " (expected sha256 " + std::string(known->sha256) + ")";
    if (blob.empty())
        throw Error(ErrorKind::Io, "unet: weights missing or unreadable" + expected, path);
    if (learned::sha256Hex(blob) != known->sha256)
        throw Error(ErrorKind::Format, "unet: weights corrupt" + expected, path);
    return blob;
}

// Why weight file `name` cannot be used (empty when it can): checkedWeights' one line. An intact
// file is checked once per path.
std::string weightsProblem(const std::string& name) {
    static std::mutex mutex;
    static std::set<std::string> intact;
    const std::string path = weightsPath(name);
    const std::lock_guard lock(mutex);
    if (intact.count(path)) return {};
    try {
        checkedWeights(name, path);
    } catch (const Error& e) {
        return e.what();
    }
    intact.insert(path);
    return {};
}

// The network of weight file `name` for `channels` inputs, loaded and checked once per path.
std::shared_ptr<const UNetNetwork> network(const std::string& name, int channels) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const UNetNetwork>> cache;
    const std::string path = weightsPath(name);
    const std::lock_guard lock(mutex);
    if (auto it = cache.find(path); it != cache.end()) return it->second;
    const std::vector<std::uint8_t> blob = checkedWeights(name, path);
    auto net = std::make_shared<const UNetNetwork>(learned::parseTza(blob, path), channels, path);
    cache.emplace(path, net);
    return net;
}

// The feature set used on `frame` for the resolved parameters.
Features featuresFor(const FrameBuffers& frame, const ParamValues& params) {
    const auto f = Features(detail::paramInt(params, "features"));
    if (f != Features::Auto) return f;
    if (!frame.has(Layer::Albedo)) return Features::Color;
    return frame.has(Layer::Normal) ? Features::AlbedoNormal : Features::Albedo;
}

// Whether the albedo and normal are noise-free: aux = clean, or auto on a frame whose features
// were prefiltered (kFeaturesPrefilteredKey).
bool cleanAux(const FrameBuffers& frame, const ParamValues& params) {
    const auto aux = Aux(detail::paramInt(params, "aux"));
    return aux == Aux::Clean ||
           (aux == Aux::Auto && frame.metadata().extra.count(kFeaturesPrefilteredKey) != 0);
}

// The weight files these parameters may pick on some frame, the likeliest first.
std::vector<std::string> candidateWeights(const ParamValues& params) {
    const auto f = Features(detail::paramInt(params, "features"));
    const auto aux = Aux(detail::paramInt(params, "aux"));
    const auto q = Quality(detail::paramInt(params, "quality"));
    std::vector<Features> sets{f};
    if (f == Features::Auto) sets = {Features::AlbedoNormal, Features::Albedo, Features::Color};
    std::vector<bool> cleans{aux == Aux::Clean};
    if (aux == Aux::Auto) cleans = {false, true};
    std::vector<std::string> names;
    for (Features s : sets)
        for (bool clean : cleans)
            if (std::string n = weightsName(s, clean, q);
                std::find(names.begin(), names.end(), n) == names.end())
                names.push_back(std::move(n));
    return names;
}

int channelsOf(Features f) {
    return f == Features::Color ? 3 : f == Features::Albedo ? 6 : 9;
}

// Network input of one tile (OIDN's input process): `pw` × `ph` pixels of `channels` values,
// zero outside `in`.
void fillInput(const FrameBuffers& frame, Features f, double scale, const Rect& in, int pw, int ph,
               float* buf, int channels, WorkContext& work) {
    constexpr double kMax = std::numeric_limits<float>::max();
    auto clampNaN = [](double v, double lo, double hi) {
        return std::isnan(v) ? 0.0 : std::min(std::max(v, lo), hi);
    };
    const Image& color = frame.color();
    const Image* albedo = f != Features::Color ? &frame.layer(Layer::Albedo) : nullptr;
    const Image* normal = f == Features::AlbedoNormal ? &frame.layer(Layer::Normal) : nullptr;
    const std::size_t row = std::size_t(pw) * channels;
    work.parallelFor(
        in.y0, in.y0 + ph,
        [&](int y) {
            float* dst = buf + std::size_t(y - in.y0) * row;
            // The padding at the bottom and right (to the 16-pixel grid) is zero.
            if (y >= in.y1) {
                std::fill_n(dst, row, 0.0f);
                return;
            }
            std::fill(dst + std::size_t(in.width()) * channels, dst + row, 0.0f);
            for (int x = in.x0; x < in.x1; ++x, dst += channels) {
                const float* c = color.row(y) + std::size_t(x) * 3;
                for (int k = 0; k < 3; ++k)
                    dst[k] = float(learned::puForward(clampNaN(double(c[k]) * scale, 0.0, kMax)));
                if (albedo) {
                    const float* a = albedo->row(y) + std::size_t(x) * 3;
                    for (int k = 0; k < 3; ++k) dst[3 + k] = float(clampNaN(a[k], 0.0, 1.0));
                }
                if (normal) {
                    const float* n = normal->row(y) + std::size_t(x) * 3;
                    for (int k = 0; k < 3; ++k)
                        dst[6 + k] = float(clampNaN(n[k], -1.0, 1.0) * 0.5 + 0.5);
                }
            }
        },
        0);
}

class UNetFilter final : public Filter {
  public:
    UNetFilter() {
        auto fixed = [](ParamSpec s) { return s.soft(s.defaultValue, s.defaultValue); };
        m_params = {
            fixed(ParamSpec::choice("features", "input features",
                                    {"auto", "color", "albedo", "albedo-normal"}, 0,
                                    "Which feature layers feed the network (auto: all present).")),
            fixed(ParamSpec::choice("aux", "feature quality", {"noisy", "clean", "auto"}, 2,
                                    "clean picks OIDN's weights for noise-free albedo and normal; "
                                    "auto: clean when the features were prefiltered.")),
            fixed(ParamSpec::choice("quality", "weights", {"fast", "balanced", "high"}, 1,
                                    "fast: small weights; high: large weights where they exist.")),
            fixed(ParamSpec("memoryMB", "memory budget (MB)", 64, 65536, 1024, ParamScale::Log,
                            true,
                            "Activation memory per tile; larger frames are tiled (same "
                            "output).")),
        };
    }
    std::string_view name() const override { return "unet"; }
    std::string_view description() const override { return kDescription; }
    const std::vector<ParamSpec>& params() const override { return m_params; }
    std::vector<Layer> requiredLayers(const ParamValues& params) const override {
        const auto f = Features(detail::paramInt(params, "features"));
        if (f == Features::Albedo) return {Layer::Albedo};
        if (f == Features::AlbedoNormal) return {Layer::Albedo, Layer::Normal};
        return {};
    }
    std::string unavailable(const ParamValues& params) const override {
        for (const std::string& name : candidateWeights(params))
            if (std::string why = weightsProblem(name); !why.empty()) return why;
        return {};
    }
    // A trained network reading a NaN as 0, as OIDN's input process does.
    FilterTraits traits() const override {
        return {FilterTraits::Output::Prediction, FilterTraits::Missing::ReadAsZero};
    }
    int margin(const ParamValues& params) const override {
        // The receptive-field half-width rounded to the tile grid (learned::UNetNetwork::overlap).
        return Quality(detail::paramInt(params, "quality")) == Quality::High ? 112 : 96;
    }

    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override {
        const Features f = featuresFor(frame, params);
        const bool clean = cleanAux(frame, params);
        const auto q = Quality(detail::paramInt(params, "quality"));
        const int channels = channelsOf(f);
        const auto net = network(weightsName(f, clean, q), channels);

        // Exposure of the whole frame, so that any region gives the same pixels.
        const double scale = learned::autoexposure(frame.color());
        const double outScale = scale != 0.0 ? 1.0 / scale : 0.0;
        const double perPixel = net->bytesPerPixel() + 4.0 * (channels + 3);
        const auto budget = std::int64_t(detail::paramValue(params, "memoryMB") * 1048576.0);
        const std::vector<learned::UNetTile> tiles = learned::planUNetTiles(
            frame.color().bounds(), roi, net->overlap(), std::int64_t(double(budget) / perPixel));

        // Progress counts pixels × layers of every tile.
        std::int64_t total = 0;
        for (const auto& t : tiles)
            total +=
                std::int64_t(learned::alignUp16(t.in.width())) * learned::alignUp16(t.in.height());
        work.expectWork(std::max<std::int64_t>(total, 1));
        const int threads = tbb::this_task_arena::max_concurrency();

        Image out(roi.width(), roi.height(), 3);
        // One workspace for all tiles: activations are allocated (and their pages touched) once.
        // The input is written and the output read in place in it (no copies).
        learned::UNetWorkspace workspace;
        for (const auto& t : tiles) {
            const int pw = learned::alignUp16(t.in.width()), ph = learned::alignUp16(t.in.height());
            // Output process: clamp at 0, inverse transfer, undo the exposure.
            auto readOutput = [&](const float* result) {
                work.parallelFor(
                    t.out.y0, t.out.y1,
                    [&](int y) {
                        const float* src =
                            result + (std::size_t(y - t.in.y0) * pw + (t.out.x0 - t.in.x0)) * 3;
                        float* dst = out.row(y - roi.y0) + std::size_t(t.out.x0 - roi.x0) * 3;
                        for (int k = 0; k < t.out.width() * 3; ++k) {
                            const double v =
                                std::isnan(src[k]) ? 0.0 : std::max(double(src[k]), 0.0);
                            dst[k] = float(learned::puInverse(v) * outScale);
                        }
                    },
                    0);
            };
            net->run(
                ph, pw,
                [&](float* input) {
                    fillInput(frame, f, scale, t.in, pw, ph, input, channels, work);
                },
                readOutput, threads, workspace,
                [&](int done, int all) {
                    (void)done;
                    work.addWork(std::int64_t(pw) * ph / all);
                    work.throwIfCancelled();
                });
        }
        return out;
    }

  private:
    std::vector<ParamSpec> m_params;
};

}  // namespace

std::unique_ptr<Filter> makeUNetFilter() {
    return std::make_unique<UNetFilter>();
}

}  // namespace glint::denoise
