// Session files: NAME.glint-session.json ("format", the layers, the view state) plus the side
// folder NAME.glint-session/ with input.exr and one weights EXR per layer (weights, painted),
// written atomically; exports of the composite.
#include <unistd.h>

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "composite/session_impl.h"
#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"

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

// Line and column of a byte offset.
std::string place(const std::string& text, std::size_t byte) {
    int line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < std::min(byte, text.size() + 1); ++i) {
        if (text[i] == '\n')
            ++line, column = 1;
        else
            ++column;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

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
            layers.push_back({{"filter", l.filter},
                              {"version", std::string(findFilter(l.filter).version())},
                              {"params", l.params},
                              {"weights", layerFile(i)}});
        }
        json view = json::object();
        for (const auto& [k, v] : viewState) view[k] = v;
        const json doc{
            {"format", kSessionFormat},
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
            out << doc.dump(2) << "\n";
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

Session Session::load(const fs::path& path, const ProgressFn& progress) {
    const std::string file = path.string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw Error(ErrorKind::Io, "session file not found", file);
    const fs::path folder = sideFolder(path);
    std::ifstream in(path, std::ios::binary);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    json doc;
    try {
        doc = json::parse(text);
    } catch (const json::parse_error& e) {
        std::string msg = e.what();
        const auto colon = msg.find(": ", msg.find("parse error"));
        if (colon != std::string::npos) msg = msg.substr(colon + 2);
        throw Error(ErrorKind::Format, "malformed or truncated session: " + msg, file,
                    place(text, e.byte));
    } catch (const json::exception& e) {
        throw Error(ErrorKind::Format, std::string("malformed session: ") + e.what(), file);
    }
    std::string where = "/";
    try {
        where = "/format";
        const int format = doc.at("format").get<int>();
        if (format > kSessionFormat)
            throw Error(ErrorKind::Format,
                        "session format " + std::to_string(format) +
                            " is newer than this Glint reads (" + std::to_string(kSessionFormat) +
                            "); update Glint",
                        file, where);
        if (format < 1) throw Error(ErrorKind::Format, "session format must be >= 1", file, where);
        where = "/input";
        const fs::path inputFile = folder / doc.at("input").get<std::string>();
        if (!fs::is_regular_file(inputFile, ec))
            throw Error(ErrorKind::Io, "side file '" + inputFile.string() + "' not found", file,
                        where);
        FrameBuffers input = readExr(inputFile);
        where = "/width";
        if (input.width() != doc.at("width").get<int>() ||
            input.height() != doc.at("height").get<int>())
            throw Error(ErrorKind::Format,
                        "the input is " + std::to_string(input.width()) + "x" +
                            std::to_string(input.height()) + ", the session says otherwise",
                        file, where);
        SessionOptions options;
        where = "/prefilter";
        options.prefilter = doc.at("prefilter").get<bool>();
        where = "/prefilterParams";
        options.prefilterParams = doc.at("prefilterParams").get<ParamValues>();
        Session session(std::move(input), options);
        Impl& s = *session.m_impl;
        where = "/bank";
        if (!doc.at("bank").is_null()) session.bankDir = doc.at("bank").get<std::string>();
        where = "/region";
        if (!doc.at("region").is_null()) {
            const auto r = doc.at("region").get<std::vector<int>>();
            if (r.size() != 4) throw Error(ErrorKind::Format, "expected [x0, x1, y0, y1]");
            session.region = Rect{r[0], r[1], r[2], r[3]};
        }
        where = "/view";
        for (const auto& item : doc.at("view").items())
            session.viewState[item.key()] = item.value().get<std::string>();
        const json& layers = doc.at("layers");
        for (std::size_t i = 0; i < layers.size(); ++i) {
            where = "/layers/" + std::to_string(i);
            const json& l = layers[i];
            SessionLayer layer;
            layer.filter = l.at("filter").get<std::string>();
            const Filter& f = findFilter(layer.filter);
            layer.params = resolveParams(f, l.at("params").get<ParamValues>());
            const fs::path mapsFile = folder / l.at("weights").get<std::string>();
            if (!fs::is_regular_file(mapsFile, ec))
                throw Error(ErrorKind::Io, "side file '" + mapsFile.string() + "' not found", file,
                            where + "/weights");
            const Image maps = readImage(mapsFile, false);
            if (maps.width() != session.width() || maps.height() != session.height() ||
                maps.channels() != 2)
                throw Error(ErrorKind::Format,
                            "side file '" + mapsFile.string() + "' is " +
                                std::to_string(maps.width()) + "x" + std::to_string(maps.height()) +
                                "x" + std::to_string(maps.channels()) + ", expected " +
                                std::to_string(session.width()) + "x" +
                                std::to_string(session.height()) + "x2",
                            file, where + "/weights");
            layer.weights = maps.channelsSlice(0, 1);
            layer.painted = maps.channelsSlice(1, 1);
            for (float& v : layer.weights.data())
                if (!(v >= 0.0f && v <= 1.0f))
                    throw Error(ErrorKind::Format,
                                "weights outside [0, 1] in '" + mapsFile.string() + "'", file,
                                where + "/weights");
            // Filters are deterministic: the output is recomputed, bit for bit what was saved.
            ProgressFn part;
            if (progress)
                part = [&, i](double fr) {
                    return progress((double(i) + fr) / double(layers.size()));
                };
            layer.output = runLayerFilter(s.filterInput(), layer.filter, layer.params, part);
            s.layers.push_back(std::move(layer));
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
    } catch (const json::exception& e) {
        throw Error(ErrorKind::Format, std::string("unexpected content: ") + e.what(), file, where);
    }
}

std::vector<fs::path> Session::temporaries(const fs::path& path, std::size_t layers) {
    const fs::path folder = path.parent_path() / path.stem();
    const fs::path tmpFolder = temporaryPathFor(folder);
    std::vector<fs::path> out{temporaryPathFor(path), temporaryPathFor(tmpFolder / "input.exr"),
                              tmpFolder / "input.exr"};
    for (std::size_t i = 0; i < layers; ++i) {
        out.push_back(temporaryPathFor(tmpFolder / layerFile(i)));
        out.push_back(tmpFolder / layerFile(i));
    }
    out.push_back(tmpFolder);
    return out;
}

void Session::exportExr(const fs::path& path) const {
    FrameBuffers out = m_impl->input;
    out.color() = m_impl->composite;
    out.metadata().extra["denoiseSession"] = std::to_string(m_impl->layers.size()) + " layers";
    writeExr(out, path);
}

void Session::exportPng(const fs::path& path, const DisplayOptions& display) const {
    writePng(m_impl->composite, path, display);
}

}  // namespace glint::denoise
