#include "commands.h"

#include "cli_boundary.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <vector>

#include "glint/image/error.h"
#include "glint/image/expectation.h"
#include "glint/image/flip.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/image/shard.h"

namespace glint::cli {

namespace {

using nlohmann::json;

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// A loaded image: layered EXR, or any other format read as a colour-only frame.
struct Loaded {
    FrameBuffers frame;
    bool layered = false;  ///< false: not an EXR, metadata means nothing
};

Loaded load(const std::string& file) {
    ComparedImage image = readComparedImage(file);
    return {std::move(image.frame), image.hdr};
}

/// Pixels with a NaN or ±Inf in some channel.
std::size_t nonFinitePixels(const Image& im) {
    std::size_t count = 0;
    const float* p = im.data().data();
    for (std::size_t i = 0; i < im.pixelCount(); ++i, p += im.channels())
        count += std::any_of(p, p + im.channels(), [](float v) { return !std::isfinite(v); });
    return count;
}

/// Splits "a,b,c" and parses each part as T; nullopt unless there are exactly `count` numbers.
template <typename T>
std::optional<std::vector<T>> parseList(const std::string& text, std::size_t count) {
    std::vector<T> out;
    std::size_t start = 0;
    while (start <= text.size()) {
        std::size_t end = text.find(',', start);
        if (end == std::string::npos) end = text.size();
        T value{};
        const char* first = text.data() + start;
        const char* last = text.data() + end;
        auto [ptr, ec] = std::from_chars(first, last, value);
        if (ec != std::errc() || ptr != last || first == last) return std::nullopt;
        out.push_back(value);
        start = end + 1;
    }
    if (out.size() != count) return std::nullopt;
    return out;
}

/// Parses --false-color "lo,hi" and says exactly what is wrong with a range it cannot show: not
/// two numbers, not finite, lo >= hi, two values float cannot tell apart, or a width beyond
/// float's range.
std::pair<float, float> parseFalseColorRange(const std::string& text) {
    auto bad = [&](const std::string& what) {
        return Error(ErrorKind::InvalidArgument, what + ", got '" + text + "'", "",
                     "--false-color");
    };
    const auto range = parseList<double>(text, 2);
    if (!range) throw bad("expected lo,hi (two numbers)");
    const double lo = (*range)[0], hi = (*range)[1];
    if (!std::isfinite(lo) || !std::isfinite(hi)) throw bad("expected two finite numbers");
    if (!(lo < hi)) throw bad("expected lo < hi");
    const float flo = float(lo), fhi = float(hi);
    if (!std::isfinite(flo) || !std::isfinite(fhi) || !std::isfinite(fhi - flo))
        throw bad("the range must fit a float: |lo|, |hi| and hi - lo at most 3.4e38");
    if (!(flo < fhi)) throw bad("lo and hi are the same number in float precision");
    return {flo, fhi};
}

/// The layer or single channel `name` of `frame` (empty name: colour).
Image selectLayer(const FrameBuffers& frame, const std::string& name, const std::string& file) {
    std::vector<std::string> present;
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        if (!frame.has(layer)) continue;
        present.push_back(std::string(layerDisplayName(layer)));
        if (name.empty() ? layer == Layer::Color : findLayer(name) == layer)
            return frame.layer(layer);
        for (int c = 0; c < layerInfo(layer).channels; ++c)
            if (name == channelName(layer, c)) return frame.layer(layer).channelsSlice(c, 1);
    }
    std::string list;
    for (const std::string& p : present) list += (list.empty() ? "" : ", ") + p;
    throw Error(ErrorKind::InvalidArgument,
                "no layer or channel '" + name + "' (the file has " + list +
                    "; a channel is named like albedo.G or R)",
                file, "--layer");
}

std::string formatNumber(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", v);
    return text;
}

}  // namespace

void runInfo(const InfoOptions& options) {
    const Loaded loaded = load(options.file);
    const FrameBuffers& frame = loaded.frame;
    const FrameMetadata& md = frame.metadata();

    json layers = json::array();
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        if (!frame.has(layer)) continue;
        json channels = json::array();
        for (int c = 0; c < layerInfo(layer).channels; ++c)
            channels.push_back(channelName(layer, c));
        layers.push_back({{"name", layerDisplayName(layer)},
                          {"channels", channels},
                          {"nonFinitePixels", nonFinitePixels(frame.layer(layer))}});
    }
    json metadata = nullptr;
    if (loaded.layered)
        metadata = {{"spp", md.spp},
                    {"seed", md.seed},
                    {"integrator", md.integrator},
                    {"scene", md.scene},
                    {"varianceOf", md.varianceOf},
                    {"normalSpace", md.normalSpace},
                    {"depth", md.depthKind},
                    {"nonFiniteSamples", md.nonFiniteSamples},
                    {"extra", md.extra}};

    if (options.json) {
        const json out = {{"file", options.file},     {"width", frame.width()},
                          {"height", frame.height()}, {"source", md.source},
                          {"layers", layers},         {"metadata", metadata}};
        std::cout << out.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
        return;
    }
    std::cout << options.file << ": " << frame.width() << "x" << frame.height() << ", "
              << (loaded.layered ? md.source + " channel names" : std::string("not an EXR"))
              << "\n";
    std::cout << "layers (name, channels, pixels with NaN/Inf):\n";
    for (const json& layer : layers) {
        std::string channels;
        for (const json& c : layer["channels"])
            channels += (channels.empty() ? "" : ",") + c.get<std::string>();
        std::printf("  %-16s %-44s %zu\n", layer["name"].get<std::string>().c_str(),
                    channels.c_str(), layer["nonFinitePixels"].get<std::size_t>());
    }
    std::cout.flush();
    if (!loaded.layered) return;
    std::cout << "metadata:\n";
    for (const auto& [key, value] : metadata.items()) {
        if (key == "extra") continue;
        std::cout << "  " << key << ": "
                  << (value.is_string() ? value.get<std::string>() : value.dump()) << "\n";
    }
    for (const auto& [key, value] : md.extra) std::cout << "  " << key << ": " << value << "\n";
}

int runDiff(const DiffOptions& options) {
    // Each --metric value is a metric to print or an expectation (a metric with a bound, or mc).
    std::vector<Expectation> requests;
    for (const std::string& text : options.metrics) {
        const bool bound = text.find_first_of("<>") != std::string::npos || text == "mc" ||
                           text.rfind("mc:", 0) == 0;
        if (bound) {
            requests.push_back(parseExpectation(text));
            continue;
        }
        Expectation print;
        print.text = text;
        print.metric = text;
        try {
            if (text != "flip") (void)parseMetric(text);
        } catch (const Error&) {
            throw Error(ErrorKind::InvalidArgument,
                        "expected ssim, psnr, mse, relmse, flip, flip-ldr or flip-hdr, or an "
                        "expectation such as 'ssim>=0.98' or mc, got '" +
                            text + "'",
                        "", "--metric");
        }
        requests.push_back(print);
    }
    if (requests.empty())
        throw Error(ErrorKind::InvalidArgument, "give at least one --metric (or --expect)", "",
                    "--metric");
    MetricOptions metricOptions;
    metricOptions.linear = options.linear;
    metricOptions.exposure = options.exposure;
    if (!std::isfinite(options.exposure))
        throw Error(ErrorKind::InvalidArgument, "expected a finite number of stops", "",
                    "--exposure");
    std::optional<std::vector<int>> crop;
    if (!options.crop.empty()) {
        crop = parseList<int>(options.crop, 4);
        if (!crop)
            throw Error(ErrorKind::InvalidArgument,
                        "expected four integers x0,x1,y0,y1, got '" + options.crop + "'", "",
                        "--crop");
    }
    if (!options.errorMap.empty()) {
        checkOutputPath(options.errorMap, {".png"}, "--error-map");
        removeTemporariesOnSignal({options.errorMap});
    }

    const ComparedImage image = readComparedImage(options.file);
    const ComparedImage reference = readComparedImage(options.reference);
    const bool hdr = image.hdr || reference.hdr;
    if (image.frame.width() != reference.frame.width() ||
        image.frame.height() != reference.frame.height())
        throw Error(ErrorKind::InvalidArgument,
                    "size " + std::to_string(reference.frame.width()) + "x" +
                        std::to_string(reference.frame.height()) + " differs from " + options.file +
                        " (" + std::to_string(image.frame.width()) + "x" +
                        std::to_string(image.frame.height()) + ")",
                    options.reference, "size");
    if (crop) {
        const Rect rect{(*crop)[0], (*crop)[1], (*crop)[2], (*crop)[3]};
        if (rect.empty() || intersect(rect, image.frame.color().bounds()) != rect)
            throw Error(ErrorKind::InvalidArgument,
                        "crop x " + std::to_string(rect.x0) + ".." + std::to_string(rect.x1) +
                            ", y " + std::to_string(rect.y0) + ".." + std::to_string(rect.y1) +
                            " is empty or outside the " + std::to_string(image.frame.width()) +
                            "x" + std::to_string(image.frame.height()) + " image",
                        options.file, "--crop");
        metricOptions.crop = rect;
    }
    const bool flipRequested = std::any_of(requests.begin(), requests.end(), [&](auto& r) {
        if (r.monteCarlo) return false;
        const Metric m = resolveMetric(r.metric, hdr);
        return m == Metric::FlipLdr || m == Metric::FlipHdr;
    });
    if (!options.errorMap.empty() && !flipRequested)
        throw Error(ErrorKind::InvalidArgument, "the error map is FLIP's: add --metric flip", "",
                    "--error-map");

    json results = json::array();
    int failed = 0;
    for (const Expectation& request : requests) {
        const Metric metric = request.monteCarlo ? Metric::Mse : resolveMetric(request.metric, hdr);
        json entry = {{"request", request.text}};
        try {
            if (request.monteCarlo || request.text.find_first_of("<>") != std::string::npos) {
                // An expectation: the library checks it (mc on the whole image).
                const ExpectationOutcome outcome =
                    checkExpectations(image, reference, {request}, metricOptions).front();
                entry["metric"] = request.monteCarlo ? "mc" : metricName(metric);
                entry["value"] = std::isfinite(outcome.value) ? json(outcome.value) : json(nullptr);
                entry["passed"] = outcome.passed;
                entry["message"] = outcome.message;
                if (!outcome.passed) {
                    ++failed;
                    if (!options.json)
                        std::fprintf(stderr, "glint-image: expectation failed: %s\n",
                                     outcome.message.c_str());
                } else if (!options.json) {
                    std::cout << outcome.message << "\n";
                }
            } else {
                MetricResult result;
                if (metric == Metric::FlipLdr || metric == Metric::FlipHdr) {
                    FlipOptions flipOptions;
                    flipOptions.hdr = metric == Metric::FlipHdr;
                    flipOptions.crop = metricOptions.crop;
                    const FlipResult flipped =
                        flip(image.frame.color(), reference.frame.color(), flipOptions);
                    result.value = flipped.mean;
                    result.pixels = flipped.map.pixelCount();
                    if (!options.errorMap.empty())
                        writePng(flipColorMap(flipped.map), options.errorMap);
                } else {
                    result = computeMetric(metric, image.frame.color(), reference.frame.color(),
                                           metricOptions);
                }
                // What the metric did with pixels holding NaN/Inf (see metrics.h).
                const bool ssimLike = metric == Metric::Ssim;
                entry["metric"] = metricName(metric);
                entry["value"] = std::isfinite(result.value) ? json(result.value) : json(nullptr);
                entry["finite"] = bool(std::isfinite(result.value));
                entry["pixels"] = result.pixels;
                entry["nonFinitePixels"] = result.nonFinitePixels;
                entry["nonFiniteTreatment"] = ssimLike ? "zeroed" : "excluded";
                if (!options.json) {
                    std::cout << metricName(metric) << " " << formatNumber(result.value) << "\n";
                    std::cout << "  " << result.pixels << " pixels"
                              << (crop ? " in crop " + options.crop : "") << "; "
                              << result.nonFinitePixels << " non-finite pixels "
                              << (ssimLike ? "set to 0 before filtering" : "excluded") << "\n";
                }
            }
        } catch (const Error& e) {
            // Name the image for errors about its content (too small for SSIM, all NaN...).
            if (e.file().empty()) throw Error(e.kind(), e.message(), options.file, e.where());
            throw;
        }
        results.push_back(entry);
    }

    if (options.json) {
        json out = {{"file", options.file},
                    {"reference", options.reference},
                    {"results", results},
                    {"failedExpectations", failed},
                    {"crop", crop ? json(*crop) : json(nullptr)},
                    {"linear", options.linear},
                    {"exposure", options.exposure}};
        // One metric: its fields at the top level too, as before expectations existed.
        if (results.size() == 1)
            for (const auto& [key, value] : results[0].items()) out[key] = value;
        std::cout << out.dump(-1, ' ', false, json::error_handler_t::replace) << "\n";
    }
    return failed > 0 ? 1 : 0;
}

void runConvert(const ConvertOptions& options) {
    checkOutputPath(options.output, {".png"}, "OUT");
    removeTemporariesOnSignal({options.output});
    DisplayOptions display;
    display.exposure = options.exposure;
    if (!std::isfinite(options.exposure))
        throw Error(ErrorKind::InvalidArgument, "expected a finite number of stops", "",
                    "--exposure");
    if (!options.falseColor.empty()) {
        const auto [lo, hi] = parseFalseColorRange(options.falseColor);
        display.falseColorChannel = 0;
        display.falseColorLo = lo;
        display.falseColorHi = hi;
    }

    const FrameBuffers frame = load(options.input).frame;
    const Image image = selectLayer(frame, options.layer, options.input);
    if (display.falseColorChannel >= 0 && image.channels() != 1)
        throw Error(ErrorKind::InvalidArgument,
                    "false colour shows one channel but '" +
                        (options.layer.empty() ? std::string("color") : options.layer) + "' has " +
                        std::to_string(image.channels()) +
                        "; pick one with --layer (e.g. depth.Z, albedo.G, R)",
                    options.input, "--false-color");
    writePng(image, options.output, display);
    std::cout << options.output << ": " << image.width() << "x" << image.height() << " from "
              << options.input << " (" << (options.layer.empty() ? "color" : options.layer)
              << ")\n";
}

void runMerge(const MergeOptions& options) {
    checkOutputPath(options.output, {".exr"}, "--out");
    removeTemporariesOnSignal({options.output});
    std::vector<NamedInput> inputs;
    for (const std::string& file : options.shards) inputs.push_back({file, "SHARD.exr"});
    checkOutputIsNoInput(options.output, "--out", inputs);
    // Headers first (the whole set is checked), then one input at a time.
    const auto start = std::chrono::steady_clock::now();
    const FrameBuffers merged =
        mergeShardFiles(options.shards, options.partial ? MergeKind::Partial : MergeKind::Whole);
    const double mergeSeconds = secondsSince(start);
    writeExr(merged, options.output);
    const double seconds = secondsSince(start);
    const auto range = shardInfo(merged.metadata(), options.output);
    const std::string held =
        range ? merged.metadata().extra.at("shard") : std::string("whole render");
    if (options.json) {
        json j = {{"out", options.output},
                  {"shards", options.shards.size()},
                  {"width", merged.width()},
                  {"height", merged.height()},
                  {"spp", merged.metadata().spp},
                  {"cancelled", merged.metadata().extra.count("cancelled") > 0},
                  {"partial", bool(range)},
                  {"mergeSeconds", mergeSeconds},
                  {"writeSeconds", seconds - mergeSeconds},
                  {"seconds", seconds}};
        if (range) j["range"] = {range->index, range->last(), range->count};
        std::cout << j.dump() << "\n";
    } else {
        std::printf(
            "merged %zu files into %s (%s): %dx%d, %d spp (read and merge %.3f s, total "
            "%.3f s)\n",
            options.shards.size(), options.output.c_str(), held.c_str(), merged.width(),
            merged.height(), merged.metadata().spp, mergeSeconds, seconds);
    }
}

}  // namespace glint::cli
