// Session files: NAME.glint-session.json ("format", the layers, the view state) plus the side
// folder NAME.glint-session/ with input.exr, one weights EXR per layer (weights, painted) and one
// correction EXR per auto's correction layer (result, blend), written atomically; exports of the
// composite.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "composite/correction.h"
#include "composite/session_impl.h"
#include "glint/denoise/denoised_frame.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "json_reader.h"

namespace glint::denoise {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// NAME.json → NAME (the side folder).
fs::path sideFolder(const fs::path& path) {
    if (path.extension() != ".json")
        throw Error(ErrorKind::InvalidArgument,
                    "a session file name ends in .json (NAME.glint-session.json)", path.string());
    return path.parent_path() / path.stem();
}

std::string layerFile(std::size_t i) {
    return "layer-" + std::to_string(i) + ".exr";
}

// Auto's correction of layer i: 6 channels, its result's RGB then its blend's.
std::string correctionFile(std::size_t i) {
    return "correction-" + std::to_string(i) + ".exr";
}

// The session format a file of `layers` needs: 2 for layer kinds (auto's correction), else 1,
// which Glints older than the kinds read too.
int formatFor(const std::vector<SessionLayer>& layers) {
    for (const SessionLayer& l : layers)
        if (l.correction) return 2;
    return 1;
}

// A side frame's name: letters, digits and '-', clear of the session's own files (input.exr,
// layer-N.exr, correction-N.exr). Its file is NAME.exr.
bool isFrameName(const std::string& name) {
    return !name.empty() && name != "input" && name.rfind("layer-", 0) != 0 &&
           name.rfind("correction-", 0) != 0 && std::all_of(name.begin(), name.end(), [](char c) {
               return std::isalnum(static_cast<unsigned char>(c)) || c == '-';
           });
}

constexpr const char* kFrameNameRule =
    "a side frame's name is letters, digits and '-', not \"input\", \"layer-...\" nor "
    "\"correction-...\"";

void removeQuietly(const fs::path& p) {
    std::error_code ec;
    fs::remove_all(p, ec);
}

}  // namespace

void Session::save(const fs::path& path) const {
    const Impl& s = *m_impl;
    const fs::path folder = sideFolder(path);
    const fs::path tmpFolder = temporaryPathFor(folder);
    const fs::path oldFolder = folder.parent_path() / ("." + folder.filename().string() + ".old-" +
                                                       std::to_string(::getpid()));
    std::error_code ec;
    if (!fs::is_directory(path.parent_path().empty() ? fs::path(".") : path.parent_path(), ec))
        throw Error(ErrorKind::Io, "the folder of the session does not exist", path.string());
    try {
        // 1. A fresh side folder under a temporary name.
        removeQuietly(tmpFolder);
        if (!fs::create_directory(tmpFolder, ec))
            throw Error(ErrorKind::Io, "cannot create the side folder (" + ec.message() + ")",
                        tmpFolder.string());
        writeExr(s.input, tmpFolder / "input.exr");
        json layers = json::array();
        for (std::size_t i = 0; i < s.layers.size(); ++i) {
            const SessionLayer& l = s.layers[i];
            Image maps(width(), height(), 2);
            for (std::size_t p = 0; p < maps.pixelCount(); ++p) {
                maps.data()[2 * p] = l.weights.data()[p];
                maps.data()[2 * p + 1] = l.painted.data()[p];
            }
            writeImage(maps, tmpFolder / layerFile(i));
            json layer;
            if (l.correction) {
                Image both(width(), height(), 6);
                for (std::size_t p = 0; p < maps.pixelCount(); ++p)
                    for (std::size_t c = 0; c < 3; ++c) {
                        both.data()[6 * p + c] = l.correction->result.data()[3 * p + c];
                        both.data()[6 * p + 3 + c] = l.correction->blend.data()[3 * p + c];
                    }
                writeImage(both, tmpFolder / correctionFile(i));
                layer = {{"kind", kAutoCorrection},
                         {"correction", correctionFile(i)},
                         {"weights", layerFile(i)}};
            } else {
                layer = {{"filter", l.filter},
                         {"version", std::string(findFilter(l.filter).version())},
                         {"params", detail::paramsJson(l.params)},
                         {"weights", layerFile(i)}};
            }
            if (!l.name.empty()) layer["name"] = l.name;  // optional: older files have none
            layers.push_back(std::move(layer));
        }
        json frames = json::object();
        for (const auto& [name, frame] : sideFrames) {
            if (!isFrameName(name))
                throw Error(ErrorKind::InvalidArgument,
                            std::string(kFrameNameRule) + "; got '" + name + "'", path.string(),
                            "/frames");
            writeExr(*frame, tmpFolder / (name + ".exr"));
            frames[name] = name + ".exr";
        }
        json view = json::object();
        for (const auto& [k, v] : viewState) view[k] = v;
        const json doc{
            {"format", formatFor(s.layers)},
            {"width", width()},
            {"height", height()},
            {"input", "input.exr"},
            {"prefilter", s.options.prefilter},
            {"prefilterParams", s.options.prefilterParams},
            {"bank", bankDir.empty() ? json(nullptr) : json(bankDir.string())},
            {"region", region ? json::array({region->x0, region->x1, region->y0, region->y1})
                              : json(nullptr)},
            {"view", view},
            {"layers", layers}};
        // 2. The JSON under its temporary name.
        const fs::path tmpJson = temporaryPathFor(path);
        {
            std::ofstream out(tmpJson);
            json written = doc;
            if (!frames.empty()) written["frames"] = frames;  // optional: older files have none
            out << written.dump(2) << "\n";
            out.close();
            if (!out) throw Error(ErrorKind::Io, "cannot write the session file", path.string());
        }
        // 3. Swap the folders, then the JSON: the old session stays whole until the new one is.
        const bool hadOld = fs::exists(folder, ec);
        if (hadOld) {
            removeQuietly(oldFolder);
            fs::rename(folder, oldFolder, ec);
            if (ec) throw Error(ErrorKind::Io, "cannot replace the side folder", folder.string());
        }
        fs::rename(tmpFolder, folder, ec);
        if (ec) {
            if (hadOld) fs::rename(oldFolder, folder, ec);
            throw Error(ErrorKind::Io, "cannot move the side folder into place", folder.string());
        }
        fs::rename(tmpJson, path, ec);
        if (ec) {
            removeQuietly(folder);
            if (hadOld) fs::rename(oldFolder, folder, ec);
            throw Error(ErrorKind::Io, "cannot move the session file into place", path.string());
        }
        if (hadOld) removeQuietly(oldFolder);
    } catch (...) {
        removeQuietly(tmpFolder);
        removeQuietly(temporaryPathFor(path));
        throw;
    }
}

namespace {

// Auto's correction from its side file (correctionFile): 6 channels of the session's size,
// every value finite. Throws glint::Error(Format) naming the file otherwise.
SessionCorrection readCorrection(const fs::path& path, int width, int height) {
    const Image both = readImage(path, false);
    if (both.width() != width || both.height() != height || both.channels() != 6)
        throw Error(ErrorKind::Format,
                    "is " + std::to_string(both.width()) + "x" + std::to_string(both.height()) +
                        "x" + std::to_string(both.channels()) + ", expected " +
                        std::to_string(width) + "x" + std::to_string(height) +
                        "x6 (auto's result RGB, then the blend it corrected RGB)",
                    path.string());
    SessionCorrection c{both.channelsSlice(0, 3), both.channelsSlice(3, 3)};
    const std::string problem = correctionProblem(c, width, height);
    if (!problem.empty()) throw Error(ErrorKind::Format, problem, path.string());
    return c;
}

/// The largest width or height a session holds (as the images Glint reads).
constexpr std::int64_t kMaxSide = 1 << 24;

// The region of interest, null or [x0, x1, y0, y1] inside the width × height image.
std::optional<Rect> readRegion(const detail::JsonReader& r, const json& value, int width,
                               int height) {
    if (value.is_null()) return std::nullopt;
    r.array(value, "/region", 4);
    std::int64_t v[4];
    for (int i = 0; i < 4; ++i)
        v[i] = r.integer(value[std::size_t(i)], "/region/" + std::to_string(i), 0, kMaxSide);
    const Rect region{int(v[0]), int(v[1]), int(v[2]), int(v[3])};
    if (region.empty() || intersect(region, Rect{0, width, 0, height}) != region)
        r.fail("/region", "the region [" + std::to_string(v[0]) + ", " + std::to_string(v[1]) +
                              ", " + std::to_string(v[2]) + ", " + std::to_string(v[3]) +
                              "] (x0, x1, y0, y1, half-open) is empty or not inside the " +
                              std::to_string(width) + "x" + std::to_string(height) + " image");
    return region;
}

}  // namespace

Session Session::load(const fs::path& path, const ProgressFn& progress) {
    const std::string file = path.string();
    const std::string text = detail::readJsonText(path, "session file");
    const fs::path folder = sideFolder(path);
    const json doc = detail::parseJsonText(text, file);
    const detail::JsonReader r(file);
    r.requireObject(doc, "",
                    {"format", "width", "height", "input", "prefilter", "prefilterParams", "bank",
                     "region", "view", "layers", "frames"});
    const std::int64_t format = r.integer(r.at(doc, "format", ""), "/format", 1, INT32_MAX);
    if (format > kSessionFormat)
        r.fail("/format", "session format " + std::to_string(format) +
                              " is newer than this Glint reads (" + std::to_string(kSessionFormat) +
                              "); update Glint");
    const int width = int(r.integer(r.at(doc, "width", ""), "/width", 1, kMaxSide));
    const int height = int(r.integer(r.at(doc, "height", ""), "/height", 1, kMaxSide));
    const std::string inputName = r.string(r.at(doc, "input", ""), "/input");
    SessionOptions options;
    options.prefilter = r.boolean(r.at(doc, "prefilter", ""), "/prefilter");
    options.prefilterParams = r.params(r.at(doc, "prefilterParams", ""), "/prefilterParams");
    const json& bank = r.at(doc, "bank", "");
    const std::string bankDir = bank.is_null() ? std::string() : r.string(bank, "/bank");
    const std::optional<Rect> region = readRegion(r, r.at(doc, "region", ""), width, height);
    const json& view = r.at(doc, "view", "");
    if (!view.is_object()) r.fail("/view", "expected an object of view settings");
    std::map<std::string, std::string> viewState;
    for (const auto& item : view.items())
        viewState[item.key()] = r.string(item.value(), "/view/" + item.key());
    std::map<std::string, std::string> frameFiles;
    if (doc.contains("frames")) {
        const json& frames = doc["frames"];
        if (!frames.is_object()) r.fail("/frames", "expected an object of side frames");
        for (const auto& item : frames.items()) {
            const std::string where = "/frames/" + item.key();
            if (!isFrameName(item.key())) r.fail(where, kFrameNameRule);
            if (r.string(item.value(), where) != item.key() + ".exr")
                r.fail(where, "expected \"" + item.key() + ".exr\"");
            frameFiles[item.key()] = item.key() + ".exr";
        }
    }
    const json& layers = r.array(r.at(doc, "layers", ""), "/layers");
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const std::string where = "/layers/" + std::to_string(i);
        // Format 2's layer kinds: auto's correction (older files have filter layers only).
        if (format >= 2 && layers[i].is_object() && layers[i].contains("kind")) {
            r.requireObject(layers[i], where, {"kind", "correction", "weights", "name"});
            const std::string kind = r.string(layers[i]["kind"], where + "/kind");
            if (kind != kAutoCorrection)
                r.fail(where + "/kind", "unknown layer kind '" + kind + "' (expected " +
                                            std::string(kAutoCorrection) + ")");
            for (const char* key : {"correction", "weights"})
                r.string(r.at(layers[i], key, where), where + "/" + key);
            if (layers[i].contains("name")) r.string(layers[i]["name"], where + "/name");
            continue;
        }
        r.requireObject(layers[i], where, {"filter", "version", "params", "weights", "name"});
        for (const char* key : {"filter", "version", "weights"})
            r.string(r.at(layers[i], key, where), where + "/" + key);
        if (layers[i].contains("name")) r.string(layers[i]["name"], where + "/name");
        r.params(r.at(layers[i], "params", where), where + "/params");
    }

    std::string where = "/input";
    try {
        const fs::path inputFile = folder / inputName;
        std::error_code ec;
        if (!fs::is_regular_file(inputFile, ec))
            throw Error(ErrorKind::Io, "side file '" + inputFile.string() + "' not found", file,
                        where);
        FrameBuffers input = readExr(inputFile);
        where = "/width";
        if (input.width() != width || input.height() != height)
            throw Error(ErrorKind::Format,
                        "the input is " + std::to_string(input.width()) + "x" +
                            std::to_string(input.height()) + ", the session says " +
                            std::to_string(width) + "x" + std::to_string(height),
                        file, where);
        where = "/prefilterParams";
        Session session(std::move(input), options);
        Impl& s = *session.m_impl;
        session.bankDir = bankDir;
        session.region = region;
        session.viewState = viewState;
        // A side file the session names, which must exist.
        auto namedFile = [&](const json& name) {
            const fs::path p = folder / name.get<std::string>();
            if (!fs::is_regular_file(p, ec))
                throw Error(ErrorKind::Io, "side file '" + p.string() + "' not found", file, where);
            return p;
        };
        for (std::size_t i = 0; i < layers.size(); ++i) {
            const std::string at = "/layers/" + std::to_string(i);
            const json& l = layers[i];
            SessionLayer layer;
            if (l.contains("name")) layer.name = l["name"].get<std::string>();
            const Filter* f = nullptr;
            if (l.contains("kind")) {
                where = at + "/correction";
                layer.filter = kAutoCorrection;
                auto correction = std::make_shared<SessionCorrection>(
                    readCorrection(namedFile(l["correction"]), width, height));
                layer.output = std::shared_ptr<const Image>(correction, &correction->result);
                layer.correction = std::move(correction);
            } else {
                layer.filter = l["filter"].get<std::string>();
                where = at + "/filter";
                f = &findFilter(layer.filter);
                where = at + "/params";
                layer.params = resolveParams(*f, r.params(l["params"], where));
            }
            where = at + "/weights";
            const fs::path mapsFile = namedFile(l["weights"]);
            const Image maps = readImage(mapsFile, false);
            if (maps.width() != session.width() || maps.height() != session.height() ||
                maps.channels() != 2)
                throw Error(ErrorKind::Format,
                            "side file '" + mapsFile.string() + "' is " +
                                std::to_string(maps.width()) + "x" + std::to_string(maps.height()) +
                                "x" + std::to_string(maps.channels()) + ", expected " +
                                std::to_string(session.width()) + "x" +
                                std::to_string(session.height()) + "x2",
                            file, where);
            layer.weights = maps.channelsSlice(0, 1);
            layer.painted = maps.channelsSlice(1, 1);
            for (float& v : layer.weights.data())
                if (!(v >= 0.0f && v <= 1.0f))
                    throw Error(ErrorKind::Format,
                                "weights outside [0, 1] in '" + mapsFile.string() + "'", file,
                                where);
            if (layer.correction) {
                s.layers.push_back(std::move(layer));
                continue;
            }
            // Filters are deterministic: the output is recomputed, bit for bit what was saved.
            ProgressFn part;
            if (progress)
                part = [&, i](double fr) {
                    return progress((double(i) + fr) / double(layers.size()));
                };
            // A file never runs a program by itself: an unavailable filter is not run.
            layer.unavailable = f->unavailable(layer.params);
            layer.output = std::make_shared<const Image>(
                layer.unavailable.empty()
                    ? runLayerFilter(s.filterInput(), layer.filter, layer.params, part)
                    : s.filterInput().color());
            s.layers.push_back(std::move(layer));
        }
        for (const auto& [name, sideFile] : frameFiles) {
            where = "/frames/" + name;
            const fs::path framePath = folder / sideFile;
            if (!fs::is_regular_file(framePath, ec))
                throw Error(ErrorKind::Io, "side file '" + framePath.string() + "' not found", file,
                            where);
            session.sideFrames[name] = std::make_shared<const FrameBuffers>(readExr(framePath));
        }
        s.recomposite(s.composite.bounds());
        return session;
    } catch (const Error& e) {
        if (e.kind() == ErrorKind::Cancelled) throw;
        if (e.file() == file) throw;
        // Errors from what the session names (a side file, a filter, parameters) name the
        // session and the place in it.
        const std::string inner = e.file().empty() ? "" : e.file() + ": ";
        throw Error(e.kind(), inner + e.message(), file, where);
    }
}

std::vector<fs::path> Session::temporaries(const fs::path& path, std::size_t layers) {
    const fs::path folder = path.parent_path() / path.stem();
    const fs::path tmpFolder = temporaryPathFor(folder);
    std::vector<fs::path> out{temporaryPathFor(path), temporaryPathFor(tmpFolder / "input.exr"),
                              tmpFolder / "input.exr"};
    for (std::size_t i = 0; i < layers; ++i)
        for (const std::string& name : {layerFile(i), correctionFile(i)}) {
            out.push_back(temporaryPathFor(tmpFolder / name));
            out.push_back(tmpFolder / name);
        }
    out.push_back(tmpFolder);
    return out;
}

void Session::exportExr(const fs::path& path) const {
    // The render's colour is kept as the noisy layer (denoisedFrame): the export can be denoised
    // again from it.
    FrameBuffers out = denoisedFrame(m_impl->input, m_impl->composite, 0, 0, "session");
    const std::size_t layers = m_impl->layers.size();
    out.metadata().extra["denoiseSession"] =
        std::to_string(layers) + (layers == 1 ? " layer" : " layers");
    writeExr(out, path);
}

void Session::exportPng(const fs::path& path, const DisplayOptions& display) const {
    writePng(m_impl->composite, path, display);
}

}  // namespace glint::denoise
