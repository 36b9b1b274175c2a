// Image assertions (docs/testing.md): parsing and checking expectations against a reference.
#include "glint/image/expectation.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/mc_compare.h"

namespace glint {
namespace {

constexpr double kDefaultFalseAlarmRate = 1e-4;

std::string lowerCase(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

Error badExpectation(const std::string& text, const std::string& what) {
    return Error(ErrorKind::InvalidArgument,
                 what + " in '" + text +
                     "' (expected METRIC>=X or METRIC<=X with METRIC ssim, psnr, mse, relmse, "
                     "flip, flip-ldr or flip-hdr, or mc, or mc:ALPHA)",
                 {}, "--expect");
}

bool parseFiniteNumber(const std::string& text, double& value) {
    const char* first = text.data();
    const char* last = first + text.size();
    const auto [ptr, ec] = std::from_chars(first, last, value);
    return ec == std::errc() && ptr == last && first != last && std::isfinite(value);
}

std::string boundText(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

}  // namespace

Expectation parseExpectation(const std::string& text) {
    Expectation e;
    e.text = text;
    std::string body;
    for (const char c : text)
        if (!std::isspace(static_cast<unsigned char>(c))) body += c;
    body = lowerCase(body);
    if (body == "mc" || body.rfind("mc:", 0) == 0) {
        e.monteCarlo = true;
        e.threshold = kDefaultFalseAlarmRate;
        if (body.size() > 3 && (!parseFiniteNumber(body.substr(3), e.threshold) ||
                                !(e.threshold > 0.0 && e.threshold < 1.0)))
            throw badExpectation(text, "the false-alarm rate must be a number in (0, 1)");
        return e;
    }
    const std::size_t op = body.find_first_of("<>");
    if (op == std::string::npos || op == 0) throw badExpectation(text, "no comparison");
    e.metric = body.substr(0, op);
    e.atLeast = body[op] == '>';
    std::size_t value = op + 1;
    if (value < body.size() && body[value] == '=')
        ++value;
    else
        e.strict = true;
    if (e.metric != "flip") {
        try {
            (void)parseMetric(e.metric);
        } catch (const Error&) {
            throw badExpectation(text, "unknown metric '" + e.metric + "'");
        }
    }
    if (!parseFiniteNumber(body.substr(value), e.threshold))
        throw badExpectation(text, "the bound must be a finite number");
    return e;
}

ComparedImage readComparedImage(const std::string& path) {
    std::string ext = lowerCase(std::filesystem::path(path).extension().string());
    if (ext == ".exr") return {readExr(path), true};
    const Image image = readImage(path, true);
    FrameBuffers frame(image.width(), image.height());
    Image& color = frame.color();
    // Grey for one or two channels (grey + alpha), the first three otherwise.
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            for (int c = 0; c < 3; ++c) color(x, y, c) = image(x, y, image.channels() >= 3 ? c : 0);
    frame.metadata() = FrameMetadata{};
    frame.metadata().source = "image";
    return {std::move(frame), false};
}

Metric resolveMetric(const std::string& name, bool hdr) {
    if (lowerCase(name) == "flip") return hdr ? Metric::FlipHdr : Metric::FlipLdr;
    return parseMetric(name);
}

std::vector<ExpectationOutcome> checkExpectations(const ComparedImage& image,
                                                  const ComparedImage& reference,
                                                  const std::vector<Expectation>& expectations,
                                                  const MetricOptions& options) {
    std::vector<ExpectationOutcome> outcomes;
    for (const Expectation& e : expectations) {
        ExpectationOutcome out;
        out.expectation = e;
        if (e.monteCarlo) {
            const Image* variance = image.frame.find(Layer::Variance);
            const Image* refVariance = reference.frame.find(Layer::Variance);
            if (!variance || !refVariance)
                throw Error(ErrorKind::InvalidArgument,
                            std::string("the Monte Carlo comparison needs the variance layer of "
                                        "both images; the ") +
                                (variance ? "reference" : "image") +
                                " has none (render with Glint, or give variance.R/G/B)",
                            {}, "--expect mc");
            McCompareOptions mc;
            mc.falseAlarmRate = e.threshold;
            const McCompareResult r = mcCompare(image.frame.color(), *variance,
                                                reference.frame.color(), *refVariance, mc);
            out.passed = r.passed;
            out.value = r.statistic;
            const Rect& w = r.worstWindow;
            out.message =
                "mc: worst window x " + std::to_string(w.x0) + ".." + std::to_string(w.x1) +
                ", y " + std::to_string(w.y0) + ".." + std::to_string(w.y1) + " differs by " +
                boundText(100.0 * r.relativeBias) + " %, statistic " + boundText(r.statistic) +
                (r.passed ? " <= " : " > ") + boundText(r.threshold) + " (false-alarm rate " +
                boundText(e.threshold) + ", " + std::to_string(r.windows) + " windows)";
        } else {
            const Metric metric = resolveMetric(e.metric, image.hdr || reference.hdr);
            out.value =
                computeMetric(metric, image.frame.color(), reference.frame.color(), options).value;
            const double v = out.value, b = e.threshold;
            out.passed = e.atLeast ? (e.strict ? v > b : v >= b) : (e.strict ? v < b : v <= b);
            out.message = std::string(metricName(metric)) + " " + boundText(v);
            if (out.passed)
                out.message += " meets " + e.text;
            else
                out.message +=
                    " misses " + e.text + " by " +
                    (std::isfinite(v) ? boundText(std::fabs(v - b)) : std::string("inf"));
        }
        outcomes.push_back(std::move(out));
    }
    return outcomes;
}

}  // namespace glint
