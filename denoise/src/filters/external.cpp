// external — any denoiser as a program: Glint writes the layers the program needs as files, runs
// the program, and reads back its result (docs/external-denoiser.md).
//
// The program is named by its full path and given its arguments as a list (argv: no shell ever
// reads them). In every argument the placeholders {color}, {albedo} and {normal} become the
// paths of the files Glint writes before the run, {output} the path the program must write.
// Only the layers named by a placeholder are written (and required of the frame). The files lie
// in a private folder (mkdtemp) that is removed whatever happens; the program runs there with
// stdin from /dev/null, stdout discarded and stderr kept for the error message, in its own
// process group, which is killed on timeout or when the progress callback says stop.
// Missing (NaN/Inf) input pixels are written as the mean of their finite 3×3 neighbours (0 when
// none), so the program never sees one; a result that is not the input's size or holds a
// non-finite value is an error. The program sees the whole frame, whatever the region.
//
// A file never runs a program by itself: the filter is unavailable (Filter::unavailable) until
// the user allows the program (glint/denoise/external.h).
//
// Parameters:
//   command   the program's full path, then its arguments, with placeholders (a list of strings)
//   format    file format of the exchanged images: exr (R, G, B float) or pfm (little-endian)
//   timeout   seconds the program may run, 0.1 … 86400 (default 600)
#include <stdlib.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <memory>

#include "filters/external_files.h"
#include "filters/external_process.h"
#include "filters/factories.h"
#include "filters/filter_util.h"
#include "glint/denoise/external.h"
#include "glint/image/error.h"

namespace glint::denoise {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kExternalDescription =
    "external: runs a program of the user's (a full path and its arguments, with placeholders "
    "{color}, {albedo}, {normal} and {output}) on the frame written as EXR or PFM files, and "
    "reads its result; the program must be allowed by the user (--allow-command).";

// The program sees the whole frame: its reach is unbounded.
constexpr int kWholeFrameMargin = 1 << 16;

// The input layers a placeholder names.
struct Placeholder {
    std::string_view text;
    Layer layer;
};
constexpr Placeholder kInputPlaceholders[] = {
    {"{color}", Layer::Color}, {"{albedo}", Layer::Albedo}, {"{normal}", Layer::Normal}};
constexpr std::string_view kOutputPlaceholder = "{output}";

const std::vector<std::string>& commandOf(const ParamValues& params) {
    static const std::vector<std::string> none;
    const auto it = params.strings.find("command");
    return it == params.strings.end() ? none : it->second;
}

bool mentions(const std::vector<std::string>& argv, std::string_view placeholder) {
    for (std::size_t i = 1; i < argv.size(); ++i)
        if (argv[i].find(placeholder) != std::string::npos) return true;
    return false;
}

// `text` with every occurrence of `from` replaced by `to`.
std::string replaceAll(std::string text, std::string_view from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
    return text;
}

// A private folder, removed with everything in it when the scope ends.
class TemporaryFolder {
  public:
    TemporaryFolder() {
        std::string pattern = (fs::temp_directory_path() / "glint-external-XXXXXX").string();
        if (!::mkdtemp(pattern.data()))
            throw Error(ErrorKind::Io, "cannot create a temporary folder", pattern);
        m_path = pattern;
    }
    ~TemporaryFolder() {
        std::error_code ec;
        fs::remove_all(m_path, ec);
    }
    TemporaryFolder(const TemporaryFolder&) = delete;
    TemporaryFolder& operator=(const TemporaryFolder&) = delete;
    const fs::path& path() const { return m_path; }

  private:
    fs::path m_path;
};

// A copy of a layer with every missing pixel replaced by the mean of its finite 3×3 neighbours.
Image withoutMissingPixels(const Image& layer) {
    Image out = layer;
    const int c = layer.channels();
    for (int y = 0; y < layer.height(); ++y)
        for (int x = 0; x < layer.width(); ++x) {
            if (detail::isFinitePixel(layer.row(y) + std::size_t(x) * c, c)) continue;
            double sum[4] = {0, 0, 0, 0};
            int count = 0;
            for (int j = std::max(0, y - 1); j <= std::min(layer.height() - 1, y + 1); ++j)
                for (int i = std::max(0, x - 1); i <= std::min(layer.width() - 1, x + 1); ++i)
                    if (detail::isFinitePixel(layer.row(j) + std::size_t(i) * c, c)) {
                        for (int k = 0; k < c; ++k) sum[k] += layer(i, j, k);
                        ++count;
                    }
            for (int k = 0; k < c; ++k) out(x, y, k) = count ? float(sum[k] / count) : 0.0f;
        }
    return out;
}

class ExternalFilter final : public Filter {
  public:
    ExternalFilter()
        : m_params{ParamSpec::strings("command", "program and arguments",
                                      "The program's full path, then its arguments; {color}, "
                                      "{albedo}, {normal} and {output} name the files."),
                   ParamSpec::choice("format", "file format", {"exr", "pfm"}, 0,
                                     "Format of the files the program reads and writes.")
                       .soft(0.0, 0.0),
                   ParamSpec("timeout", "timeout (s)", 0.1, 86400.0, 600.0, ParamScale::Log, false,
                             "Seconds the program may run before it is stopped.")
                       .soft(600.0, 600.0)} {}

    std::string_view name() const override { return "external"; }
    std::string_view description() const override { return kExternalDescription; }
    const std::vector<ParamSpec>& params() const override { return m_params; }

    std::vector<Layer> requiredLayers(const ParamValues& params) const override {
        std::vector<Layer> layers;
        for (const Placeholder& p : kInputPlaceholders)
            if (p.layer != Layer::Color && mentions(commandOf(params), p.text))
                layers.push_back(p.layer);
        return layers;
    }

    std::string unavailable(const ParamValues& params) const override {
        const std::vector<std::string>& argv = commandOf(params);
        if (argv.empty() || argv[0].empty())
            return "no command given (parameter 'command': the program's full path, then its "
                   "arguments)";
        if (!fs::path(argv[0]).is_absolute())
            return "the command '" + argv[0] +
                   "' is not named by its full path (an absolute path, e.g. /opt/bin/tool)";
        if (!commandAllowed(argv[0]))
            return "the command '" + argv[0] + "' is not allowed to run; " + howToAllow(argv[0]);
        return {};
    }

    int margin(const ParamValues& /*params*/) const override { return kWholeFrameMargin; }

    Image apply(const FrameBuffers& frame, const ParamValues& params, const Rect& roi,
                WorkContext& work) const override {
        const std::vector<std::string>& argv = commandOf(params);
        const std::string program = argv.empty() ? std::string() : argv[0];
        const std::string where = "command '" + program + "'";
        checkProgram(program, where);
        const auto format = detail::ExchangeFormat(detail::paramInt(params, "format"));
        const std::string extension = format == detail::ExchangeFormat::Pfm ? ".pfm" : ".exr";
        TemporaryFolder folder;

        // Write the layers the arguments name and substitute the placeholders.
        std::vector<std::string> args = argv;
        for (const Placeholder& p : kInputPlaceholders) {
            if (!mentions(argv, p.text)) continue;
            const fs::path file =
                folder.path() / (std::string(layerDisplayName(p.layer)) + extension);
            detail::writeExchangeImage(withoutMissingPixels(frame.layer(p.layer)), file, format);
            for (std::size_t i = 1; i < args.size(); ++i)
                args[i] = replaceAll(args[i], p.text, file.string());
        }
        const fs::path output = folder.path() / ("output" + extension);
        for (std::size_t i = 1; i < args.size(); ++i)
            args[i] = replaceAll(args[i], kOutputPlaceholder, output.string());

        // Run it, then check what it wrote.
        const detail::ProcessOutcome outcome =
            detail::runProcess(args, folder.path(), detail::paramValue(params, "timeout"),
                               [&] { return work.poll(); });
        checkOutcome(outcome, params, where);
        Image result = readResult(output, format, where);
        if (result.width() != frame.width() || result.height() != frame.height())
            throw Error(ErrorKind::Format,
                        "the program wrote a " + std::to_string(result.width()) + "x" +
                            std::to_string(result.height()) + " image, the input is " +
                            std::to_string(frame.width()) + "x" + std::to_string(frame.height()),
                        {}, where);
        if (const std::size_t bad = result.countNonFinite())
            throw Error(
                ErrorKind::Numeric,
                "the program's result holds " + std::to_string(bad) + " NaN or infinite value(s)",
                {}, where);
        work.addWork(roi.height());
        return result.crop(roi);
    }

  private:
    // The program must be a full path to an executable regular file.
    static void checkProgram(const std::string& program, const std::string& where) {
        std::error_code ec;
        if (program.empty() || !fs::path(program).is_absolute())
            throw Error(ErrorKind::InvalidArgument,
                        "the program is not named by its full path (an absolute path)", {}, where);
        if (!fs::exists(program, ec))
            throw Error(ErrorKind::Io, "the program does not exist", {}, where);
        if (!fs::is_regular_file(program, ec) || ::access(program.c_str(), X_OK) != 0)
            throw Error(ErrorKind::Io, "the program is not an executable file", {}, where);
    }

    void checkOutcome(const detail::ProcessOutcome& outcome, const ParamValues& params,
                      const std::string& where) const {
        using End = detail::ProcessOutcome::End;
        const std::string tail = detail::lastLines(outcome.stderrTail, 3);
        const std::string said = tail.empty() ? "" : "; its stderr ends: " + tail;
        switch (outcome.end) {
            case End::Exited:
                if (outcome.code == 0) return;
                throw Error(ErrorKind::Io,
                            "the program exited with code " + std::to_string(outcome.code) + said,
                            {}, where);
            case End::Signalled:
                throw Error(ErrorKind::Io,
                            "the program was killed by signal " + std::to_string(outcome.code) +
                                " (" + strsignal(outcome.code) + ")" + said,
                            {}, where);
            case End::TimedOut:
                throw Error(ErrorKind::Io,
                            "the program ran past its timeout of " +
                                formatParam(m_params[2], params) + " s and was stopped" + said,
                            {}, where);
            case End::Stopped:
                throw Error(ErrorKind::Cancelled, "cancelled", {}, where);
        }
    }

    static Image readResult(const fs::path& output, detail::ExchangeFormat format,
                            const std::string& where) {
        try {
            return detail::readExchangeImage(output, format);
        } catch (const Error& e) {
            const bool missing = e.kind() == ErrorKind::Io;
            throw Error(e.kind(),
                        (missing ? "the program exited without writing its output ({output}) "
                                 : "the program's output ({output}) is unreadable: ") +
                            (missing ? std::string() : e.message()),
                        {}, where);
        }
    }

    std::vector<ParamSpec> m_params;
};

}  // namespace

std::unique_ptr<Filter> makeExternalFilter() {
    return std::make_unique<ExternalFilter>();
}

}  // namespace glint::denoise
