// glint-denoise paint | composite: script a painting session, apply a saved session to a new
// render (docs/painting.md); and the session `auto --session` writes (docs/auto.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <utility>

#include "cli_boundary.h"
#include "commands.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/paint_script.h"
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

void runPaint(const PaintArgs& a) {
    // Outputs first, then the script (it must be valid before the render is read).
    if (fs::path(a.save).extension() != ".json")
        throw Error(ErrorKind::InvalidArgument,
                    "a session file name ends in .json (NAME.glint-session.json)", {}, "--save");
    glint::cli::checkOutputPath(a.save, {".json"}, "--save");
    if (!a.out.empty()) glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.png.empty()) glint::cli::checkOutputPath(a.png, {".png"}, "--png");
    for (const auto& [output, flag] :
         {std::pair{a.save, "--save"}, std::pair{a.out, "--out"}, std::pair{a.png, "--png"}})
        glint::cli::checkOutputIsNoInput(output, flag, {{a.input, "IN"}, {a.script, "--script"}});
    checkOutsideSessionFolder(a.out, "--out", a.save, "--save");
    checkOutsideSessionFolder(a.png, "--png", a.save, "--save");
    const PaintScript script = PaintScript::read(a.script);

    std::vector<std::string> temporaries;
    for (const fs::path& p : Session::temporaries(a.save, script.layers().size()))
        temporaries.push_back(p.string());
    glint::cli::removeOnSignal(temporaries);                // the session's
    glint::cli::removeTemporariesOnSignal({a.out, a.png});  // the exports' (empty: none)

    const auto t0 = std::chrono::steady_clock::now();
    SessionOptions options;
    options.prefilter = a.prefilter;
    const InputFrame input = readInput(a.input);
    Session session(input.frame, options);
    sayInput(input);
    script.apply(session);
    session.save(a.save);
    if (!a.out.empty()) session.exportExr(a.out);
    if (!a.png.empty()) session.exportPng(a.png);
    const double seconds = secondsSince(t0);
    if (a.json) {
        printJson({{"input", a.input},
                   {"session", a.save},
                   {"layers", session.layerCount()},
                   {"edits", script.editCount()},
                   {"seconds", seconds}});
        return;
    }
    std::printf("painted %zu layers with %zu edits in %.2f s -> %s\n", session.layerCount(),
                script.editCount(), seconds, a.save.c_str());
}

// ---- composite -------------------------------------------------------------------------------

// Warns on stderr about every layer of the session that was not run (an external program the
// user has not allowed); returns them as [{"layer", "filter", "reason"}].
json reportUnavailableLayers(const Session& session, const std::string& file) {
    json list = json::array();
    for (std::size_t i = 0; i < session.layerCount(); ++i) {
        const SessionLayer& l = session.layer(i);
        if (l.unavailable.empty()) continue;
        std::fprintf(stderr,
                     "glint-denoise: warning: %s: layer %zu (%s) is unavailable and left out: %s\n",
                     file.c_str(), i, l.filter.c_str(), oneLine(l.unavailable).c_str());
        list.push_back({{"layer", i}, {"filter", l.filter}, {"reason", l.unavailable}});
    }
    return list;
}

struct CompositeArgs {
    std::string session, input, out, png, reference;
    bool json = false;
};

void runComposite(const CompositeArgs& a) {
    glint::cli::checkOutputPath(a.out, {".exr"}, "--out");
    if (!a.png.empty()) glint::cli::checkOutputPath(a.png, {".png"}, "--png");
    for (const auto& [output, flag] : {std::pair{a.out, "--out"}, std::pair{a.png, "--png"}}) {
        glint::cli::checkOutputIsNoInput(
            output, flag,
            {{a.session, "SESSION"}, {a.input, "--input"}, {a.reference, "--reference"}});
        checkOutsideSessionFolder(output, flag, a.session, "SESSION");
    }
    glint::cli::removeTemporariesOnSignal({a.out, a.png});
    const auto t0 = std::chrono::steady_clock::now();
    Session session = Session::load(a.session);
    const json unavailable = reportUnavailableLayers(session, a.session);
    InputFrame input = readInput(a.input);
    FrameBuffers& render = input.frame;
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
    sayInput(input);
    session.reapply(std::move(render));
    json report{{"session", a.session},
                {"input", a.input},
                {"output", a.out},
                {"layers", session.layerCount()}};
    if (!unavailable.empty()) report["unavailable"] = unavailable;
    if (reference) {
        report["metricsInput"] = metricsOf(session.input().color(), reference->color(), {});
        report["metrics"] = metricsOf(session.composite(), reference->color(), {});
    }
    session.exportExr(a.out);
    if (!a.png.empty()) session.exportPng(a.png);
    report["seconds"] = secondsSince(t0);
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

void checkSessionOutput(const std::string& session, const char* flag,
                        const std::vector<std::pair<std::string, const char*>>& inputs,
                        const std::vector<std::pair<std::string, const char*>>& outputs) {
    if (session.empty()) return;
    glint::cli::checkOutputPath(session, {".json"}, flag);
    std::vector<glint::cli::NamedInput> named;
    for (const auto& [path, inputFlag] : inputs)
        if (!path.empty()) named.push_back({path, inputFlag});
    glint::cli::checkOutputIsNoInput(session, flag, named);
    // The save replaces the side folder: it must be no input, nor hold one.
    const fs::path side = fs::path(session).parent_path() / fs::path(session).stem();
    for (const auto& [path, inputFlag] : inputs) {
        std::error_code ec;
        if (path.empty()) continue;
        const fs::path folder =
            fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
        if ((fs::equivalent(path, side, ec) && !ec) || (fs::equivalent(folder, side, ec) && !ec))
            throw Error(ErrorKind::InvalidArgument,
                        "the side folder of the session, '" + side.string() +
                            "', is or holds the input given by " + inputFlag + " ('" + path +
                            "'); saving the session would replace it",
                        {}, flag);
    }
    for (const auto& [path, outputFlag] : outputs)
        checkOutsideSessionFolder(path, outputFlag, session, flag);
}

std::size_t writeAutoSession(const std::string& path, const FrameBuffers& frame,
                             const BankOptions& bankOptions, const FilterBank& bank,
                             const AutoResult& result) {
    // At most one layer per member and auto's correction.
    std::vector<std::string> temporaries;
    for (const fs::path& p : Session::temporaries(path, result.layers.size() + 1))
        temporaries.push_back(p.string());
    glint::cli::removeOnSignal(temporaries);
    SessionOptions options;
    options.prefilter = bankOptions.prefilter;
    options.prefilterParams = bankOptions.prefilterParams;
    Session session(frame, options);
    startFromAuto(session, bank, result);
    session.save(path);
    return session.layerCount();
}

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
