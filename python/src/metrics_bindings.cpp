// Metrics from Python: MSE, relMSE, PSNR, SSIM and their maps, FLIP, the Monte Carlo comparison,
// and the expectations of image assertions (glint.testing).
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.h"
#include "glint/image/error.h"
#include "glint/image/expectation.h"
#include "glint/image/flip.h"
#include "glint/image/mc_compare.h"
#include "glint/image/metrics.h"

namespace glint::python {
namespace {

MetricOptions metricOptions(float exposure, bool linear, py::handle crop) {
    MetricOptions options;
    options.exposure = exposure;
    options.linear = linear;
    options.crop = regionFrom(crop);
    return options;
}

/// Binds a scalar metric `name` computed by `fn`.
void bindMetric(py::module_& m, const char* name,
                MetricResult (*fn)(const Image&, const Image&, const MetricOptions&),
                const char* doc) {
    m.def(
        name,
        [fn](py::handle image, py::handle reference, float exposure, bool linear, py::handle crop) {
            const ImageArg a(image, "image"), b(reference, "reference");
            const MetricOptions options = metricOptions(exposure, linear, crop);
            py::gil_scoped_release release;
            return fn(a.get(), b.get(), options).value;
        },
        py::arg("image"), py::arg("reference"), py::arg("exposure") = 0.0f,
        py::arg("linear") = false, py::arg("crop") = py::none(), doc);
}

/// Binds a per-pixel map `name` computed by `fn`.
void bindMap(py::module_& m, const char* name,
             Image (*fn)(const Image&, const Image&, const MetricOptions&)) {
    m.def(
        name,
        [fn](py::handle image, py::handle reference, float exposure, bool linear, py::handle crop) {
            const ImageArg a(image, "image"), b(reference, "reference");
            const MetricOptions options = metricOptions(exposure, linear, crop);
            py::gil_scoped_release release;
            return fn(a.get(), b.get(), options);
        },
        py::arg("image"), py::arg("reference"), py::arg("exposure") = 0.0f,
        py::arg("linear") = false, py::arg("crop") = py::none());
}

FlipToneMapper parseToneMapper(const std::string& name) {
    if (name == "aces") return FlipToneMapper::Aces;
    if (name == "hable") return FlipToneMapper::Hable;
    if (name == "reinhard") return FlipToneMapper::Reinhard;
    throw Error(ErrorKind::InvalidArgument,
                "unknown tone mapper '" + name + "' (aces, hable, reinhard)", {}, "tone_mapper");
}

/// An image to compare: a file name (read as glint-image diff reads it) or a FrameBuffers (HDR).
ComparedImage compared(py::handle object, const std::string& what) {
    if (py::isinstance<FrameBuffers>(object)) return {object.cast<const FrameBuffers&>(), true};
    if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__"))
        return readComparedImage(py::str(py::module_::import("os").attr("fspath")(object)));
    throw Error(ErrorKind::InvalidArgument,
                std::string("is a ") + Py_TYPE(object.ptr())->tp_name +
                    "; expected a file name or a glint.FrameBuffers",
                {}, what);
}

}  // namespace

void bindMetrics(py::module_& m) {
    bindMetric(m, "mse", &mse, "Mean squared error over pixels and channels (linear values).");
    bindMetric(m, "relmse", &relMse, "pbrt's relative MSE: mean of (x - r)^2 / (r^2 + 1e-2).");
    bindMetric(m, "psnr", &psnr, "PSNR in dB for data range 1 (linear values).");
    bindMetric(m, "ssim", &ssim,
               "SSIM (Wang et al. 2004) on display values at `exposure` unless linear.");
    bindMap(m, "abs_error_map", &absErrorMap);
    bindMap(m, "rel_error_map", &relErrorMap);
    bindMap(m, "ssim_map", &ssimMap);

    py::class_<FlipResult>(m, "FlipResult", "A FLIP evaluation: mean, per-pixel map, exposures.")
        .def_readonly("mean", &FlipResult::mean)
        .def_readonly("map", &FlipResult::map)
        .def_readonly("start_exposure", &FlipResult::startExposure)
        .def_readonly("stop_exposure", &FlipResult::stopExposure)
        .def_readonly("exposures", &FlipResult::exposures);
    m.def(
        "flip",
        [](py::handle image, py::handle reference, bool hdr, double ppd,
           const std::string& toneMapper, std::optional<double> start, std::optional<double> stop,
           int exposures, py::handle crop) {
            const ImageArg a(image, "image"), b(reference, "reference");
            FlipOptions options;
            options.hdr = hdr;
            options.pixelsPerDegree = ppd;
            options.toneMapper = parseToneMapper(toneMapper);
            options.startExposure = start;
            options.stopExposure = stop;
            options.exposures = exposures;
            options.crop = regionFrom(crop);
            py::gil_scoped_release release;
            return flip(a.get(), b.get(), options);
        },
        py::arg("image"), py::arg("reference"), py::arg("hdr") = false,
        py::arg("pixels_per_degree") = kFlipDefaultPixelsPerDegree, py::arg("tone_mapper") = "aces",
        py::arg("start_exposure") = py::none(), py::arg("stop_exposure") = py::none(),
        py::arg("exposures") = 0, py::arg("crop") = py::none(),
        "LDR-FLIP (values in [0, 1]) or HDR-FLIP (hdr=True) of linear RGB images.");

    py::class_<McCompareResult>(m, "McCompareResult", "The Monte Carlo comparison's outcome.")
        .def_readonly("passed", &McCompareResult::passed)
        .def_readonly("statistic", &McCompareResult::statistic)
        .def_readonly("threshold", &McCompareResult::threshold)
        .def_property_readonly("worst_window",
                               [](const McCompareResult& r) { return regionTuple(r.worstWindow); })
        .def_readonly("relative_bias", &McCompareResult::relativeBias)
        .def_readonly("windows", &McCompareResult::windows)
        .def("__bool__", [](const McCompareResult& r) { return r.passed; });
    m.def(
        "mc_compare",
        [](py::handle mean, py::handle variance, py::handle reference, py::handle referenceVariance,
           double falseAlarmRate) {
            const ImageArg a(mean, "mean"), av(variance, "variance"), b(reference, "reference"),
                bv(referenceVariance, "reference_variance");
            McCompareOptions options;
            options.falseAlarmRate = falseAlarmRate;
            py::gil_scoped_release release;
            return mcCompare(a.get(), av.get(), b.get(), bv.get(), options);
        },
        py::arg("mean"), py::arg("variance"), py::arg("reference"), py::arg("reference_variance"),
        py::arg("false_alarm_rate") = 1e-4,
        "Whether two Monte Carlo estimates differ by more than their variances of the mean explain "
        "(docs/testing.md), at the stated false-alarm rate.");

    m.def(
        "check_expectations",
        [](py::handle image, py::handle reference, const std::vector<std::string>& expectations) {
            std::vector<Expectation> parsed;
            for (const std::string& text : expectations) parsed.push_back(parseExpectation(text));
            const ComparedImage a = compared(image, "image"), b = compared(reference, "reference");
            std::vector<ExpectationOutcome> outcomes;
            {
                py::gil_scoped_release release;
                outcomes = checkExpectations(a, b, parsed);
            }
            py::list list;
            for (const ExpectationOutcome& o : outcomes) {
                py::dict d;
                d["expectation"] = o.expectation.text;
                d["passed"] = o.passed;
                d["value"] = o.value;
                d["message"] = o.message;
                list.append(d);
            }
            return list;
        },
        py::arg("image"), py::arg("reference"), py::arg("expectations"),
        "Checks expectations ('ssim>=0.98', 'flip<=0.05', 'mc'...) as glint-image diff --expect: "
        "one dict per expectation (passed, value, message).");
}

}  // namespace glint::python
