// Denoising from Python: every registered filter by name with its parameters (ParamSpec), the
// filter bank, the automatic selection (auto) and painting sessions' composites.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <memory>

#include "bindings.h"
#include "glint/denoise/auto.h"
#include "glint/denoise/auto_stream.h"
#include "glint/denoise/bank.h"
#include "glint/denoise/registry.h"
#include "glint/denoise/session.h"
#include "glint/image/error.h"

namespace glint::python {
namespace {

namespace fs = std::filesystem;
using namespace glint::denoise;

/// Parameter values for `specs` from a Python dict (see numbersFromDict).
ParamValues paramValues(const std::vector<ParamSpec>& specs, py::handle values,
                        const std::string& where) {
    ParamValues out;
    std::map<std::string, std::vector<std::string>> strings;
    static_cast<std::map<std::string, double>&>(out) =
        numbersFromDict(specs, values, where, &strings);
    out.strings = std::move(strings);
    return out;
}

py::dict filterDict(const Filter& filter, bool inDefaultBank) {
    py::dict d;
    d["name"] = std::string(filter.name());
    d["version"] = std::string(filter.version());
    d["description"] = std::string(filter.description());
    py::list params;
    for (const ParamSpec& spec : filter.params()) params.append(specDict(spec));
    d["params"] = params;
    d["default_bank"] = inDefaultBank;
    return d;
}

py::dict memberDict(const BankMember& member) {
    py::dict d;
    d["filter"] = member.filter;
    d["params"] =
        valuesDict(findFilter(member.filter).params(), member.params, member.params.strings);
    d["is_default"] = member.isDefault;
    return d;
}

/// Runs `work` in an arena of `threads` threads (0: the whole pool).
void inArena(int threads, const std::function<void()>& work) {
    if (threads < 0 || threads > 1024)
        throw Error(ErrorKind::InvalidArgument, "expected 0 (all) to 1024", {}, "threads");
    if (threads == 0) {
        work();
        return;
    }
    tbb::task_arena arena(threads);
    arena.execute(work);
}

/// The bank and the options of its build a Python caller gives by keyword.
BankOptions bankOptions(int size, std::uint64_t seed, py::handle filters, py::handle filterParams,
                        bool prefilter, py::handle region, py::handle cacheDir,
                        std::uint64_t memoryLimit) {
    BankOptions options;
    options.size = size;
    options.seed = seed;
    if (!filters.is_none()) options.filters = filters.cast<std::vector<std::string>>();
    if (!filterParams.is_none())
        for (const auto& [name, values] : filterParams.cast<py::dict>()) {
            const std::string filter = py::str(name);
            options.filterParams[filter] =
                paramValues(findFilter(filter).params(), values, "filter_params['" + filter + "']");
        }
    options.prefilter = prefilter;
    options.region = regionFrom(region);
    // None, not "": pybind11 gives an empty path to Python as Path("."), the current folder.
    if (!cacheDir.is_none()) options.cacheDir = cacheDir.cast<fs::path>();
    options.memoryLimit = memoryLimit;
    validate(options);
    return options;
}

/// What auto gives back to Python.
struct PyAutoResult {
    AutoResult result;
    std::shared_ptr<FilterBank> bank;
};

}  // namespace

void bindDenoise(py::module_& m) {
    m.def(
        "filters",
        [] {
            py::list list;
            const std::vector<const Filter*> bank = defaultBankFilters();
            for (const Filter* f : allFilters())
                list.append(filterDict(*f, std::find(bank.begin(), bank.end(), f) != bank.end()));
            return list;
        },
        "Every registered filter: name, description, params (their descriptions), default_bank.");
    m.def("render_of", &renderOf, py::arg("frame"),
          "The render a frame holds: the frame itself, or for a denoised file that keeps its "
          "render (glint-final's, glint-denoise's, a studio export; layer 'noisy') the frame with "
          "that render as its colour, as the commands denoise it.");
    m.def(
        "filter_info", [](const std::string& name) { return filterDict(findFilter(name), false); },
        py::arg("name"));
    m.def(
        "apply_filter",
        [](const FrameBuffers& frame, const std::string& name, py::handle params, py::handle region,
           py::object progress, int threads) {
            const Filter& filter = findFilter(name);
            const ParamValues values = paramValues(filter.params(), params, "params");
            FilterOptions options;
            options.region = regionFrom(region);
            options.threads = threads;
            Job job(std::move(progress));
            options.progress = job.progressFn();
            Image out;
            job.run([&] { out = applyFilter(filter, frame, values, options); });
            return out;
        },
        py::arg("frame"), py::arg("filter"), py::arg("params") = py::none(),
        py::arg("region") = py::none(), py::arg("progress") = py::none(), py::arg("threads") = 0,
        "Applies a filter by name to the frame's colour (or a region (x0, y0, x1, y1)); params "
        "by name (a choice by its option name). Returns a glint.Image of the region's size.");

    py::class_<FilterBank, std::shared_ptr<FilterBank>>(m, "Bank",
                                                        "A computed filter bank: members and "
                                                        "their results over its region.")
        .def("__len__", &FilterBank::size)
        .def_property_readonly("members",
                               [](const FilterBank& b) {
                                   py::list list;
                                   for (const BankMember& member : b.members())
                                       list.append(memberDict(member));
                                   return list;
                               })
        .def(
            "result",
            [](py::object self, int i) {
                const FilterBank& b = self.cast<const FilterBank&>();
                if (i < 0 || std::size_t(i) >= b.size())
                    throw py::index_error("no member " + std::to_string(i) + " (the bank has " +
                                          std::to_string(b.size()) + ")");
                return imageView(b.result(std::size_t(i)), self, false);
            },
            py::arg("member"), "Member i's result over the region: a read-only numpy view.")
        .def_property_readonly("region",
                               [](const FilterBank& b) { return regionTuple(b.region()); })
        .def_property_readonly("cache_hits", &FilterBank::cacheHits);

    m.def(
        "build_bank",
        [](const FrameBuffers& frame, int size, std::uint64_t seed, py::handle filters,
           py::handle filterParams, bool prefilter, py::handle region, py::handle cacheDir,
           std::uint64_t memoryLimit, py::object progress, int threads) {
            BankOptions options = bankOptions(size, seed, filters, filterParams, prefilter, region,
                                              cacheDir, memoryLimit);
            if (!options.cacheDir.empty()) {
                // As glint-denoise bank: the cache folder is made when missing.
                std::error_code ec;
                fs::create_directories(options.cacheDir, ec);
                if (ec)
                    throw Error(ErrorKind::Io,
                                "cannot create the bank folder (" + ec.message() + ")",
                                options.cacheDir.string(), "cache_dir");
            }
            Job job(std::move(progress));
            options.progress = job.progressFn();
            auto bank = std::make_shared<FilterBank>();
            job.run([&] { inArena(threads, [&] { *bank = buildBank(frame, options); }); });
            return bank;
        },
        py::arg("frame"), py::arg("size") = 64, py::arg("seed") = 1,
        py::arg("filters") = py::none(), py::arg("filter_params") = py::none(),
        py::arg("prefilter") = false, py::arg("region") = py::none(),
        py::arg("cache_dir") = py::none(), py::arg("memory_limit") = 0,
        py::arg("progress") = py::none(), py::arg("threads") = 0,
        "Builds the filter bank of a frame (glint-denoise bank): Latin-hypercube members of the "
        "filters (the default bank's unless named) plus each filter's defaults.");

    py::class_<PyAutoResult>(m, "AutoResult", "The automatic selection's result.")
        .def_property_readonly("composite",
                               [](const PyAutoResult& r) { return Image(r.result.composite); })
        .def_property_readonly("choice",
                               [](const PyAutoResult& r) { return Image(r.result.choice); })
        .def_property_readonly("best_member",
                               [](const PyAutoResult& r) { return r.result.bestMember; })
        .def_property_readonly("estimated_mse",
                               [](const PyAutoResult& r) { return r.result.estimatedMse; })
        .def_property_readonly(
            "estimator",
            [](const PyAutoResult& r) { return autoEstimatorName(r.result.estimator); })
        .def_property_readonly("stacked", [](const PyAutoResult& r) { return r.result.stacked; })
        .def_property_readonly("bank", [](const PyAutoResult& r) { return r.bank; });

    m.def(
        "auto",
        [](const FrameBuffers& input, std::shared_ptr<FilterBank> bank, const std::string& quality,
           const std::string& estimator, float exposure, std::uint64_t seed, py::handle size,
           std::uint64_t bankSeed, py::handle filters, py::handle tuning, py::object progress,
           int threads) {
            const AutoQuality q = parseAutoQuality(quality);
            AutoOptions options;
            options.tuning = autoQualityTuning(q);
            for (const auto& [name, value] : paramValues(autoTuningSpecs(), tuning, "tuning"))
                options.tuning[name] = value;
            options.seed = seed;
            options.exposure = exposure;
            options.estimator = parseAutoEstimator(estimator);
            validate(options);
            checkAutoInput(input, options.estimator);
            // As glint-denoise auto: without variance or halves, the image-only estimate, and a
            // bank built here on the frame without a variance layer the estimator does not read.
            FrameBuffers frame = input;
            if (resolveEstimator(options.estimator, frame) == AutoEstimator::Image) {
                options.estimator = AutoEstimator::Image;
                if (!bank) frame.remove(Layer::Variance);
            }
            Job job(std::move(progress));
            options.progress = job.progressFn();
            PyAutoResult out;
            if (bank) {
                out.bank = std::move(bank);
                job.run([&] {
                    inArena(threads,
                            [&] { out.result = autoComposite(*out.bank, frame, options); });
                });
                return out;
            }
            const BankOptions b =
                bankOptions(size.is_none() ? autoQualityBankSize(q) : size.cast<int>(), bankSeed,
                            filters, py::none(), false, py::none(), py::none(), 0);
            job.run([&] {
                inArena(threads, [&] {
                    StreamedAuto s = autoCompositeStreamed(frame, b, options);
                    out.result = std::move(s.result);
                    out.bank = std::make_shared<FilterBank>(std::move(s.bank));
                });
            });
            return out;
        },
        py::arg("frame"), py::arg("bank") = nullptr, py::arg("quality") = "balanced",
        py::arg("estimator") = "auto", py::arg("exposure") = 0.0f, py::arg("seed") = 1,
        py::arg("size") = py::none(), py::arg("bank_seed") = 1, py::arg("filters") = py::none(),
        py::arg("tuning") = py::none(), py::arg("progress") = py::none(), py::arg("threads") = 0,
        "The automatic selection (glint-denoise auto): every member's error estimated without a "
        "reference, the per-pixel composite. Builds the quality's bank unless one is given.");

    py::class_<Session>(m, "Session", "A painting session (docs/painting.md), as saved.")
        .def_property_readonly(
            "composite",
            [](py::object self) {
                return imageView(self.cast<const Session&>().composite(), self, false);
            },
            "The composite colour: a read-only numpy view.")
        .def_property_readonly("input", [](const Session& s) { return FrameBuffers(s.input()); })
        .def_property_readonly("width", &Session::width)
        .def_property_readonly("height", &Session::height)
        .def_property_readonly("layers",
                               [](const Session& s) {
                                   py::list list;
                                   for (std::size_t i = 0; i < s.layerCount(); ++i) {
                                       const SessionLayer& layer = s.layer(i);
                                       py::dict d;
                                       d["filter"] = layer.filter;
                                       d["name"] = layer.name;
                                       d["unavailable"] = layer.unavailable;
                                       if (!layer.correction)
                                           d["params"] =
                                               valuesDict(findFilter(layer.filter).params(),
                                                          layer.params, layer.params.strings);
                                       list.append(d);
                                   }
                                   return list;
                               })
        .def(
            "export_exr", [](const Session& s, const fs::path& path) { s.exportExr(path); },
            py::arg("path"),
            "The input's layers with the colour replaced by the composite, the input's colour "
            "kept as layer 'noisy'.");
    m.def(
        "load_session",
        [](const fs::path& path, py::object progress) {
            Job job(std::move(progress));
            std::unique_ptr<Session> session;
            job.run([&] {
                session = std::make_unique<Session>(Session::load(path, job.progressFn()));
            });
            return session;
        },
        py::arg("path"), py::arg("progress") = py::none(),
        "Loads a saved session (NAME.glint-session.json), re-running its layers' filters.");
}

}  // namespace glint::python
