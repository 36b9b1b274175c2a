// glint-denoise's subcommands, one file per group: filter_commands.cpp (list, apply),
// bank_commands.cpp (bank), session_commands.cpp (paint, composite, the session auto writes),
// auto_commands.cpp (auto), and the helpers they share (cli_util.cpp). Private to the CLIs:
// glint-denoise, and glint-lab (lab/cli/), which reuses them through the glint_denoise_cli library.
#pragma once

#include <CLI/CLI.hpp>

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "glint/denoise/filter.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/image.h"

namespace glint::denoise {
class FilterBank;
struct AutoOptions;
struct AutoResult;
struct BankOptions;
}  // namespace glint::denoise

namespace glint::denoise::cli {

/// A registered subcommand and what runs it when it was given on the command line.
struct Command {
    CLI::App* app = nullptr;
    std::function<void()> run;
};

std::vector<Command> addFilterCommands(CLI::App& app);
std::vector<Command> addBankCommands(CLI::App& app);
std::vector<Command> addSessionCommands(CLI::App& app);
std::vector<Command> addAutoCommands(CLI::App& app);

/// Seconds since `t` (steady clock).
double secondsSince(std::chrono::steady_clock::time_point t);
/// Splits a comma-separated list, dropping empty items.
std::vector<std::string> splitList(const std::string& text);
/// Member `m` of `bank` as JSON (index, filter, params, default); null for m < 0.
nlohmann::json memberJson(const FilterBank& bank, int m);

/// Parameter values as one JSON object (lists of strings as arrays).
nlohmann::json paramsJson(const ParamValues& params);

/// Allows the programs of --allow-command and of the user's allowed-commands file
/// (glint/denoise/external.h); call once the command line is parsed.
void allowCommands(const std::vector<std::string>& given);

/// Splits "name=value"; `option` names the flag in the error.
std::pair<std::string, std::string> splitKeyValue(const std::string& text,
                                                  const std::string& option);

/// Parses every "name=value" against `specs` (a choice takes an option name or its index) and
/// resolves them; `owner` names the filter or the prefilter in errors, `option` the flag.
ParamValues parseParams(const std::vector<std::string>& given, const std::vector<ParamSpec>& specs,
                        const std::string& owner, const std::string& option);

/// Parses every "FILTER.NAME=VALUE" of `option` (--filter-param; VALUE as --param reads it: a
/// number, a choice's option name, or a JSON array of strings) into fixed parameters by filter
/// (BankOptions::filterParams): checked against the filter's parameters, only those given kept.
std::map<std::string, ParamValues> parseFilterParams(const std::vector<std::string>& given,
                                                     const std::string& option);

/// Takes the "prefilter.NAME=VALUE" items out of `given` (bank's --filter-param, apply's --param)
/// and parses them as the feature prefilter's parameters (radius, sigmaSpatial, varianceScale);
/// `option` names the flag in errors. Refuses them when the features are not prefiltered
/// (`prefilter` false).
ParamValues takePrefilterParams(std::vector<std::string>& given, bool prefilter,
                                const std::string& option);

/// The help of --filter-param (bank, auto).
inline constexpr const char* kFilterParamHelp =
    "Fixed parameter of one filter, filter.name=value, held by every member of that filter "
    "(repeatable; the value as apply's --param reads it, e.g. "
    "'external.command=[\"/opt/bin/tool\",\"{color}\",\"{output}\"]')";

/// Warns on stderr, one line per member, of the members of `bank` that cannot run here and were
/// left out (an external program not allowed: the reason says how to allow it), naming `source`
/// (the bank folder or the input); returns them for a --json report ({filter, params, reason}).
nlohmann::json reportUnavailableMembers(const FilterBank& bank, const std::string& source);

/// Parses a whole decimal integer (an optional '-', then digits: no '+', spaces, hexadecimal or
/// exponent, no overflow); `flag` names the option in the error. Ranges are checked by the
/// options' validate().
int parseInteger(const std::string& text, const char* flag);
/// parseInteger for an option that may be left out: nullopt for "".
std::optional<int> parseOptionalInteger(const std::string& text, const char* flag);
/// Parses a whole decimal number (std::from_chars: no spaces or trailing characters); `flag`
/// names the option in the error. Ranges are checked by the options' validate().
double parseNumber(const std::string& text, const char* flag);

/// Refuses before any work an output (a file) inside the side folder of the session file
/// `session` (NAME.glint-session.json → NAME.glint-session/): writing there would replace the
/// session's input or weights, or be removed by the session's next save.
void checkOutsideSessionFolder(const std::string& output, const char* outputFlag,
                               const std::string& session, const char* sessionFlag);

/// Refuses before any work a session file `session` (given by `flag`) that cannot be written
/// where asked: not NAME.json in a writable folder, one of `inputs` (path, flag; by file
/// identity), or a side folder (NAME/) that is one of `inputs` (a bank folder) or holds one; and
/// each of `outputs` (path, flag) inside that side folder.
void checkSessionOutput(const std::string& session, const char* flag,
                        const std::vector<std::pair<std::string, const char*>>& inputs,
                        const std::vector<std::pair<std::string, const char*>>& outputs);

/// Writes the session that starts from auto's result (startFromAuto; docs/auto.md, "Starting a
/// session from auto"): `frame`, the input auto read, with the filters reading its features as
/// the bank's did (`bankOptions`), saved atomically to `path` (its temporaries registered for
/// removal on a signal first). Returns its layer count.
std::size_t writeAutoSession(const std::string& path, const FrameBuffers& frame,
                             const BankOptions& bankOptions, const FilterBank& bank,
                             const AutoResult& result);

/// Refuses before any work an output that is one of the files of the bank folder `bankDir` (its
/// index or a member), compared by file identity.
void checkOutputIsNoBankFile(const std::string& output, const char* outputFlag,
                             const std::string& bankDir);

/// Parses "x0,x1,y0,y1" (half-open pixel rectangle); `option` names the flag in errors.
Rect parseRect(const std::string& text, const std::string& option = "--roi");

/// What is wrong with `r` as a region of a width × height image ("" when nothing): which bound
/// makes it empty or which lies past the image.
std::string regionProblem(const Rect& r, int width, int height);

/// parseRect, then checks the rectangle is non-empty and inside a width × height frame read
/// from `file`.
Rect parseRegion(const std::string& text, int width, int height, const std::string& file,
                 const std::string& option = "--roi");

/// A rectangle as JSON: [x0, x1, y0, y1] (half-open).
nlohmann::json rectJson(const Rect& r);

/// Writes the per-pixel choice among `members` bank members (a 1-channel member index) as a
/// false-colour PNG, the ramp spanning member 0 … members − 1.
void writeChoiceMap(const Image& choice, std::size_t members, const std::string& path);

/// The auto composite's options (its defaults) for a bank read from the folder `bankDir`: the
/// features prefiltered as the bank's were (readBankOptions).
AutoOptions autoOptionsOfBank(const std::string& bankDir);

/// The input EXR a command denoises (readInput).
struct InputFrame {
    FrameBuffers frame;          ///< the render it holds (denoise::renderOf)
    std::optional<Image> shown;  ///< a denoised file's own colour (kept around a region)
    std::string note;            ///< "IN keeps its render (layer noisy): …", or empty
};
/// Reads the input EXR a command denoises: the render it holds, and for a denoised file that
/// keeps its render (layer noisy) its own colour and the line that says so.
InputFrame readInput(const std::string& path);
/// Prints input.note on stderr (nothing when empty): when the command's checks have passed and
/// its work starts, so that bad input still gets one line.
void sayInput(const InputFrame& input);

/// Reads a reference EXR of the given size (errors name the file).
FrameBuffers readReference(const std::string& path, int width, int height);

/// SSIM (null for a region smaller than its 11×11 window), PSNR and relMSE of `image` against
/// `reference`, over `crop` when given.
nlohmann::json metricsOf(const Image& image, const Image& reference,
                         const std::optional<Rect>& crop);

/// The parameter table of a filter or of the prefilter as JSON.
nlohmann::json describe(const std::vector<ParamSpec>& specs);

/// For a bank without a filter list (options.filters empty), built here or reopened from its
/// folder: the default filters left out because they cannot run here (unet without its weights),
/// each said once on stderr, as a JSON array of {filter, reason} (empty when none).
nlohmann::json reportLeftOutFilters(const BankOptions& options);

/// Prints one JSON object on stdout (invalid UTF-8 replaced).
void printJson(const nlohmann::json& j);

}  // namespace glint::denoise::cli
