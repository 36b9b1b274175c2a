// glint-denoise paint | composite: script a painting session, apply a saved session to a new
// render (docs/painting.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/paint.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"

namespace glint::denoise::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---- paint -----------------------------------------------------------------------------------

struct PaintArgs {
    std::string input, script, save, out, png;
    bool prefilter = false, json = false;
};

// Reads a script value, turning nlohmann's errors into one naming the script and the place.
class Script {
  public:
    Script(std::string file, const json& root) : m_file(std::move(file)), m_root(root) {}

    [[noreturn]] void fail(const std::string& where, const std::string& what) const {
        throw Error(ErrorKind::Format, what, m_file, where);
    }
    const json& at(const json& object, const std::string& key, const std::string& where) const {
        if (!object.is_object()) fail(where, "expected an object");
        if (!object.contains(key)) fail(where + "/" + key, "missing required key '" + key + "'");
        return object[key];
    }
    double number(const json& v, const std::string& where) const {
        if (!v.is_number()) fail(where, "expected a number, got " + v.dump());
        return v.get<double>();
    }
    std::size_t layer(const json& v, const std::string& where, std::size_t count) const {
        if (!v.is_number_integer() || v.get<long long>() < 0 ||
            v.get<long long>() >= (long long)count)
            fail(where,
                 "expected a layer index in [0, " + std::to_string(count) + "), got " + v.dump());
        return std::size_t(v.get<long long>());
    }
    BrushMode mode(const json& object, const std::string& where) const {
        if (!object.contains("mode")) return BrushMode::Add;
        const json& m = object["mode"];
        if (m == "add") return BrushMode::Add;
        if (m == "subtract") return BrushMode::Subtract;
        fail(where + "/mode", "expected \"add\" or \"subtract\", got " + m.dump());
    }
    const std::string& file() const { return m_file; }
    const json& root() const { return m_root; }

  private:
    std::string m_file;
    const json& m_root;
};

json readScript(const std::string& file) {
    std::ifstream in(file);
    if (!in) throw Error(ErrorKind::Io, "cannot read the paint script", file);
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    try {
        return json::parse(text);
    } catch (const json::parse_error& e) {
        // "line L, column C" of the byte nlohmann stopped at, and its message without the
        // "[json.exception…] parse error at …: " preamble.
        int line = 1, column = 1;
        for (std::size_t i = 0; i + 1 < std::min<std::size_t>(e.byte, text.size() + 1); ++i)
            if (text[i] == '\n')
                ++line, column = 1;
            else
                ++column;
        std::string what = e.what();
        const std::size_t colon = what.find(": ", what.find("parse error"));
        if (colon != std::string::npos) what = what.substr(colon + 2);
        throw Error(ErrorKind::Format, "malformed JSON: " + what, file,
                    "line " + std::to_string(line) + ", column " + std::to_string(column));
    }
}

// Filter parameters from the script: numbers, or option names for choice parameters.
ParamValues scriptParams(const Script& sc, const Filter& f, const json& params,
                         const std::string& where) {
    ParamValues values;
    if (params.is_null()) return values;
    if (!params.is_object()) sc.fail(where, "expected an object of parameters");
    for (const auto& item : params.items()) {
        const ParamSpec* spec = findParam(f.params(), item.key());
        const std::string place = where + "/" + item.key();
        if (!spec) {
            values[item.key()] = 0.0;  // resolveParams names the valid ones
            continue;
        }
        try {
            values[item.key()] = item.value().is_string()
                                     ? parseParamValue(*spec, item.value().get<std::string>())
                                     : sc.number(item.value(), place);
        } catch (const Error& e) {
            sc.fail(place, e.message());
        }
    }
    try {
        return resolveParams(f, values);
    } catch (const Error& e) {
        sc.fail(where, e.message());
    }
}

void runEdit(const Script& sc, Session& session, const json& edit, const std::string& where) {
    if (!edit.is_object() || edit.size() != 1)
        sc.fail(where,
                "expected one of {\"stroke\": …}, {\"fill\": …}, {\"diffuse\": …}, "
                "{\"weights\": …}");
    const std::string kind = edit.begin().key();
    const json& e = edit.begin().value();
    const std::string at = where + "/" + kind;
    const std::size_t count = session.layerCount();
    if (kind == "stroke") {
        const std::size_t layer = sc.layer(sc.at(e, "layer", at), at + "/layer", count);
        Brush brush;
        brush.size = sc.number(sc.at(e, "size", at), at + "/size");
        if (e.contains("softness")) brush.softness = sc.number(e["softness"], at + "/softness");
        try {
            validate(brush);
        } catch (const Error& err) {
            sc.fail(at, err.message());
        }
        const json& points = sc.at(e, "points", at);
        if (!points.is_array() || points.empty()) sc.fail(at + "/points", "expected [[x, y], …]");
        session.beginStroke(layer, brush, sc.mode(e, at));
        for (std::size_t i = 0; i < points.size(); ++i) {
            const std::string p = at + "/points/" + std::to_string(i);
            if (!points[i].is_array() || points[i].size() != 2) sc.fail(p, "expected [x, y]");
            session.dab(sc.number(points[i][0], p + "/0"), sc.number(points[i][1], p + "/1"));
        }
        session.endStroke();
    } else if (kind == "fill") {
        const std::size_t layer = sc.layer(sc.at(e, "layer", at), at + "/layer", count);
        const json& wand = sc.at(e, "wand", at);
        const json& seed = sc.at(wand, "seed", at + "/wand");
        if (!seed.is_array() || seed.size() != 2) sc.fail(at + "/wand/seed", "expected [x, y]");
        const double sx = sc.number(seed[0], at + "/wand/seed/0");
        const double sy = sc.number(seed[1], at + "/wand/seed/1");
        if (!(sx >= 0 && sx < session.width() && sy >= 0 && sy < session.height()))
            sc.fail(at + "/wand/seed", "the seed lies outside the " +
                                           std::to_string(session.width()) + "x" +
                                           std::to_string(session.height()) + " image");
        WandOptions options;
        for (auto [key, field] : {std::pair{"color", &options.color},
                                  {"albedo", &options.albedo},
                                  {"normal", &options.normal},
                                  {"depth", &options.depth}})
            if (wand.contains(key)) *field = sc.number(wand[key], at + "/wand/" + key);
        Image seeds(session.width(), session.height(), 1, 0.0f);
        seeds(int(sx), int(sy), 0) = 1.0f;
        session.fill(layer, magicWand(session.filterInput(), seeds, options), sc.mode(e, at));
    } else if (kind == "diffuse") {
        const json& layers = sc.at(e, "layers", at);
        if (!layers.is_array() || layers.empty()) sc.fail(at + "/layers", "expected [index, …]");
        std::vector<std::size_t> list;
        for (std::size_t i = 0; i < layers.size(); ++i)
            list.push_back(sc.layer(layers[i], at + "/layers/" + std::to_string(i), count));
        try {
            session.diffuse(list);
        } catch (const Error& err) {
            sc.fail(at, err.message());
        }
    } else if (kind == "weights") {
        const std::size_t layer = sc.layer(sc.at(e, "layer", at), at + "/layer", count);
        const double value = sc.number(sc.at(e, "value", at), at + "/value");
        if (!(value >= 0.0 && value <= 1.0)) sc.fail(at + "/value", "expected a weight in [0, 1]");
        session.setWeights(layer, Image(session.width(), session.height(), 1, float(value)));
    } else {
        sc.fail(at, "unknown edit '" + kind + "' (expected stroke, fill, diffuse or weights)");
    }
}

void runPaint(const PaintArgs& a) {
    // Outputs first, then the script (it must be valid before the render is read).
    if (fs::path(a.save).extension() != ".json")
        throw Error(ErrorKind::InvalidArgument,
                    "a session file name ends in .json (NAME.glint-session.json)", {}, "--save");
    glint::cli::checkOutputPath(a.save, {".json"}, "--save");
    if (!a.out.empty()) glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.png.empty()) glint::cli::checkOutputPath(a.png, {".png"}, "--png");
    const json root = readScript(a.script);
    const Script sc(a.script, root);
    const json& layers = sc.at(root, "layers", "");
    if (!layers.is_array()) sc.fail("/layers", "expected an array of layers");
    std::vector<std::pair<std::string, ParamValues>> specs;
    for (std::size_t i = 0; i < layers.size(); ++i) {
        const std::string where = "/layers/" + std::to_string(i);
        const json& name = sc.at(layers[i], "filter", where);
        if (!name.is_string()) sc.fail(where + "/filter", "expected a filter name");
        const Filter* f = nullptr;
        try {
            f = &findFilter(name.get<std::string>());
        } catch (const Error& e) {
            sc.fail(where + "/filter", e.message());
        }
        specs.push_back(
            {std::string(f->name()),
             scriptParams(sc, *f, layers[i].contains("params") ? layers[i]["params"] : json(),
                          where + "/params")});
    }
    const json edits = root.contains("edits") ? root["edits"] : json::array();
    if (!edits.is_array()) sc.fail("/edits", "expected an array of edits");

    std::vector<std::string> temporaries;
    for (const fs::path& p : Session::temporaries(a.save, specs.size()))
        temporaries.push_back(p.string());
    glint::cli::removeOnSignal(temporaries);                // the session's
    glint::cli::removeTemporariesOnSignal({a.out, a.png});  // the exports' (empty: none)

    const auto t0 = std::chrono::steady_clock::now();
    SessionOptions options;
    options.prefilter = a.prefilter;
    Session session(readExr(a.input), options);
    for (const auto& [filter, params] : specs) session.addLayer(filter, params);
    for (std::size_t i = 0; i < edits.size(); ++i)
        runEdit(sc, session, edits[i], "/edits/" + std::to_string(i));
    session.save(a.save);
    if (!a.out.empty()) session.exportExr(a.out);
    if (!a.png.empty()) session.exportPng(a.png);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (a.json) {
        printJson({{"input", a.input},
                   {"session", a.save},
                   {"layers", session.layerCount()},
                   {"edits", edits.size()},
                   {"seconds", seconds}});
        return;
    }
    std::printf("painted %zu layers with %zu edits in %.2f s -> %s\n", session.layerCount(),
                edits.size(), seconds, a.save.c_str());
}

// ---- composite -------------------------------------------------------------------------------

struct CompositeArgs {
    std::string session, input, out, png, reference;
    bool json = false;
};

void runComposite(const CompositeArgs& a) {
    glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.png.empty()) glint::cli::checkOutputPath(a.png, {".png"}, "--png");
    glint::cli::removeTemporariesOnSignal({a.out, a.png});
    const auto t0 = std::chrono::steady_clock::now();
    Session session = Session::load(a.session);
    FrameBuffers render = readExr(a.input);
    if (render.width() != session.width() || render.height() != session.height())
        throw Error(ErrorKind::InvalidArgument,
                    "the new render is " + std::to_string(render.width()) + "x" +
                        std::to_string(render.height()) + " but the session " + a.session +
                        " was painted on " + std::to_string(session.width()) + "x" +
                        std::to_string(session.height()),
                    a.input, "--input");
    std::optional<FrameBuffers> reference;
    if (!a.reference.empty())
        reference = readReference(a.reference, render.width(), render.height());
    session.reapply(std::move(render));
    json report{{"session", a.session},
                {"input", a.input},
                {"output", a.out},
                {"layers", session.layerCount()}};
    if (reference) {
        report["metricsInput"] = metricsOf(session.input().color(), reference->color(), {});
        report["metrics"] = metricsOf(session.composite(), reference->color(), {});
    }
    session.exportExr(a.out);
    if (!a.png.empty()) session.exportPng(a.png);
    report["seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (a.json) {
        printJson(report);
        return;
    }
    std::printf("composited %zu layers of %s onto %s -> %s\n", session.layerCount(),
                a.session.c_str(), a.input.c_str(), a.out.c_str());
    if (reference)
        std::printf("  vs %s: SSIM %.4f -> %.4f\n", a.reference.c_str(),
                    report["metricsInput"]["ssim"].get<double>(),
                    report["metrics"]["ssim"].get<double>());
}

}  // namespace

std::vector<Command> addSessionCommands(CLI::App& app) {
    auto paint = std::make_shared<PaintArgs>();
    CLI::App* paintCmd =
        app.add_subcommand("paint", "Build a painting session from a script of layers and edits");
    paintCmd->add_option("IN", paint->input, "Input layered EXR")->required();
    paintCmd->add_option("--script", paint->script, "Paint script (JSON, docs/painting.md)")
        ->required();
    paintCmd->add_option("--save", paint->save, "Session file NAME.glint-session.json")->required();
    paintCmd->add_option("--out", paint->out, "Also write the composite as a layered EXR");
    paintCmd->add_option("--png", paint->png, "Also write the composite as a PNG");
    paintCmd->add_flag("--prefilter", paint->prefilter, "Filters read prefiltered features");
    paintCmd->add_flag("--json", paint->json, "Print one JSON object on stdout");

    auto comp = std::make_shared<CompositeArgs>();
    CLI::App* compCmd =
        app.add_subcommand("composite", "Apply a saved session to a new render of the same scene");
    compCmd->add_option("SESSION", comp->session, "Session file (.json)")->required();
    compCmd->add_option("--input", comp->input, "New render (layered EXR, same size)")->required();
    compCmd->add_option("--out", comp->out, "Composite as a layered EXR")->required();
    compCmd->add_option("--png", comp->png, "Also write the composite as a PNG");
    compCmd->add_option("--reference", comp->reference, "Reference EXR: print SSIM before/after");
    compCmd->add_flag("--json", comp->json, "Print one JSON object on stdout");
    return {{paintCmd, [paint] { runPaint(*paint); }}, {compCmd, [comp] { runComposite(*comp); }}};
}

}  // namespace glint::denoise::cli
