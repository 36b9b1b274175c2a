#include "bank/bank_cache.h"

#include <signal.h>

#include <bit>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "glint/denoise/prefilter.h"
#include "glint/denoise/registry.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/random.h"
#include "json_reader.h"

namespace glint::denoise {

namespace fs = std::filesystem;
using nlohmann::json;

namespace detail {

namespace {

constexpr int kIndexFormat = 1;
constexpr const char* kIndexName = "index.json";
constexpr const char* kPartialPrefix = "index.members-";

std::uint64_t hashString(std::uint64_t h, const std::string& s) {
    for (unsigned char c : s) h = mix64(h ^ c) + 0x9e3779b97f4a7c15ULL;
    return hash64(h, s.size());
}

std::uint64_t hashDouble(std::uint64_t h, double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    return hash64(h, bits);
}

std::uint64_t hashParams(std::uint64_t h, const ParamValues& params) {
    for (const auto& [name, value] : params) h = hashDouble(hashString(h, name), value);
    for (const auto& [name, list] : params.strings) {
        h = hashString(h, name);
        for (const std::string& item : list) h = hashString(h, item);
    }
    return h;
}

json filterParamsJson(const std::map<std::string, ParamValues>& fixed) {
    json out = json::object();
    for (const auto& [filter, params] : fixed) out[filter] = paramsJson(params);
    return out;
}

json regionJson(const Rect& r) {
    return json::array({r.x0, r.x1, r.y0, r.y1});
}

// True when `text` is all decimal digits (and not empty).
bool allDigits(std::string_view text) {
    return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
}

// True when no process `pid` runs on this machine.
bool processEnded(long pid) {
    return ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}

// The member entries ({key, file, checksum}) of an index or a partial index, checked.
std::map<std::uint64_t, std::pair<std::string, std::uint64_t>> readEntries(const JsonReader& r,
                                                                           const json& index) {
    std::map<std::uint64_t, std::pair<std::string, std::uint64_t>> entries;
    const json& members = r.array(r.at(index, "members", ""), "/members");
    for (std::size_t i = 0; i < members.size(); ++i) {
        const std::string where = "/members/" + std::to_string(i);
        const json& m = members[i];
        try {
            const std::string file = r.string(r.at(m, "file", where), where + "/file");
            // A member file lies in the folder: a name with a path in it is not one.
            if (file.find('/') != std::string::npos || file.empty() || file[0] == '.')
                r.fail(where + "/file", "expected a file name in the bank folder");
            entries[fromHex(r.string(r.at(m, "key", where), where + "/key"))] = {
                file, fromHex(r.string(r.at(m, "checksum", where), where + "/checksum"))};
        } catch (const Error& e) {
            if (e.file() == r.file()) throw;
            r.fail(where, e.message());
        }
    }
    return entries;
}

// "format" (at most kIndexFormat) and "inputHash" of an index or a partial index.
std::uint64_t readInputHash(const JsonReader& r, const json& index) {
    const std::int64_t format = r.integer(r.at(index, "format", ""), "/format", 1, INT32_MAX);
    if (format > kIndexFormat)
        r.fail("/format", "index format " + std::to_string(format) +
                              " is newer than this Glint reads (" + std::to_string(kIndexFormat) +
                              ")");
    try {
        return fromHex(r.string(r.at(index, "inputHash", ""), "/inputHash"));
    } catch (const Error& e) {
        if (e.file() == r.file()) throw;
        r.fail("/inputHash", e.message());
    }
}

}  // namespace

long bankTemporaryOwner(const std::string& name) {
    // "." STEM ".tmp-" PID EXT, with STEM and EXT those of a file a build writes.
    const std::size_t tmp = name.rfind(".tmp-");
    if (name.size() < 2 || name[0] != '.' || tmp == std::string::npos) return 0;
    const std::string stem = name.substr(1, tmp - 1);
    const std::string rest = name.substr(tmp + 5);
    const std::size_t dot = rest.find('.');
    if (dot == std::string::npos) return 0;
    const std::string pid = rest.substr(0, dot), ext = rest.substr(dot);
    const bool member = stem.size() == 18 && stem.rfind("m-", 0) == 0 &&
                        stem.find_first_not_of("0123456789abcdef", 2) == std::string::npos &&
                        ext == ".exr";
    bool partial = false;
    if (stem.rfind(kPartialPrefix, 0) == 0) {
        const std::string range = stem.substr(std::strlen(kPartialPrefix));
        const std::size_t dash = range.find('-');
        partial = dash != std::string::npos && allDigits(range.substr(0, dash)) &&
                  allDigits(range.substr(dash + 1));
    }
    const bool index = (stem == "index" || partial) && ext == ".json";
    long owner = 0;
    const auto [end, ec] = std::from_chars(pid.data(), pid.data() + pid.size(), owner);
    if (!(member || index) || !allDigits(pid) || ec != std::errc() ||
        end != pid.data() + pid.size() || owner <= 0)
        return 0;
    return owner;
}

std::string toHex(std::uint64_t value) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
    return text;
}

std::uint64_t fromHex(const std::string& text) {
    if (text.size() != 16 || text.find_first_not_of("0123456789abcdef") != std::string::npos)
        throw Error(ErrorKind::Format, "expected 16 hexadecimal digits, got '" + text + "'");
    return std::stoull(text, nullptr, 16);
}

std::uint64_t hashImage(const Image& image) {
    std::uint64_t h = hash64(std::uint64_t(image.width()) << 32 | std::uint64_t(image.height()),
                             std::uint64_t(image.channels()));
    const std::span<const float> data = image.data();
    for (float v : data) {
        std::uint32_t bits;
        std::memcpy(&bits, &v, 4);
        h = mix64(h ^ bits) + 0x9e3779b97f4a7c15ULL;
    }
    return h;
}

BankCache::BankCache(fs::path dir, std::uint64_t inputHash, int width, int height,
                     const BankOptions& options)
    : m_dir(std::move(dir)),
      m_inputHash(inputHash),
      m_width(width),
      m_height(height),
      m_options(options) {
    std::ostringstream pre;
    pre << (options.prefilter ? "prefilter" : "raw");
    if (options.prefilter)
        for (const auto& [k, v] :
             resolveParams(prefilterParams(), options.prefilterParams, "feature prefilter"))
            pre << " " << k << "=" << toHex(std::bit_cast<std::uint64_t>(v));
    m_prefilterKey = pre.str();
    if (m_dir.empty()) return;
    // Entries of an existing index for this input; anything unreadable means no entries.
    const fs::path index = m_dir / kIndexName;
    std::ifstream in(index);
    if (!in) return;
    try {
        const std::string text{std::istreambuf_iterator<char>(in), {}};
        const JsonReader r(index.string());
        const json j = parseJsonText(text, r.file());
        if (readInputHash(r, j) != m_inputHash) return;
        for (const auto& [key, entry] : readEntries(r, j))
            m_entries[key] = {entry.first, entry.second};
    } catch (const Error&) {
        m_entries.clear();  // a damaged index is ignored: everything is recomputed
    }
}

std::uint64_t memberKey(std::uint64_t inputHash, const std::string& filter,
                        std::string_view version, const ParamValues& params,
                        const std::string& prefilterKey, const Rect& region) {
    std::uint64_t h = hash64(inputHash, 0x62616e6bULL);  // "bank"
    h = hashString(h, filter);
    h = hashString(h, std::string(version));
    h = hashParams(h, params);
    h = hashString(h, prefilterKey);
    h = hash64(h, std::uint64_t(std::uint32_t(region.x0)) << 32 | std::uint32_t(region.x1));
    h = hash64(h, std::uint64_t(std::uint32_t(region.y0)) << 32 | std::uint32_t(region.y1));
    return h;
}

std::uint64_t BankCache::key(const BankMember& member, const Rect& region) const {
    return memberKey(m_inputHash, member.filter, findFilter(member.filter).version(), member.params,
                     m_prefilterKey, region);
}

bool BankCache::read(std::uint64_t key, const Rect& region, Image& out) const {
    if (m_dir.empty()) return false;
    Entry entry;
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        const auto it = m_entries.find(key);
        if (it == m_entries.end()) return false;
        entry = it->second;
    }
    try {
        FrameBuffers frame = readExr(m_dir / entry.file);
        if (frame.width() != region.width() || frame.height() != region.height()) return false;
        const auto k = frame.metadata().extra.find("bankKey");
        if (k == frame.metadata().extra.end() || k->second != toHex(key)) return false;
        if (hashImage(frame.color()) != entry.checksum) return false;
        out = std::move(frame.color());
        return true;
    } catch (const Error&) {
        return false;  // unreadable or truncated: recompute, never trust it
    }
}

void BankCache::write(std::uint64_t key, const BankMember& member, const Rect& region,
                      const Image& result) {
    if (m_dir.empty()) return;
    FrameBuffers frame(region.width(), region.height());
    frame.color() = result;
    FrameMetadata& meta = frame.metadata();
    meta.extra["bankKey"] = toHex(key);
    meta.extra["bankFilter"] = member.filter;
    const std::string file = "m-" + toHex(key) + ".exr";
    writeExr(frame, m_dir / file);
    const std::lock_guard<std::mutex> lock(m_mutex);
    m_entries[key] = {file, hashImage(result)};
}

json BankCache::optionsJson() const {
    return {{"size", m_options.size},
            {"seed", m_options.seed},
            {"filters", m_options.filters},
            {"filterParams", filterParamsJson(m_options.filterParams)},
            {"prefilter", m_options.prefilter},
            {"prefilterParams", m_options.prefilterParams},
            {"region", m_options.region ? regionJson(*m_options.region) : json(nullptr)}};
}

void BankCache::writePartialIndex(const std::vector<BankMember>& members,
                                  const std::vector<std::uint64_t>& keys, std::size_t first,
                                  std::size_t end, const Rect& region) {
    if (m_dir.empty()) return;
    json list = json::array();
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        for (std::size_t i = first; i < end; ++i) {
            const Entry& e = m_entries.at(keys[i]);
            list.push_back({{"filter", members[i].filter},
                            {"key", toHex(keys[i])},
                            {"file", e.file},
                            {"checksum", toHex(e.checksum)}});
        }
    }
    const json partial{{"format", kIndexFormat},
                       {"inputHash", toHex(m_inputHash)},
                       {"region", regionJson(region)},
                       {"options", optionsJson()},
                       {"first", first},
                       {"end", end},
                       {"members", list}};
    const fs::path path = m_dir / (std::string(kPartialPrefix) + std::to_string(first) + "-" +
                                   std::to_string(end) + ".json");
    writeAtomically(path, [&](const fs::path& tmp) {
        std::ofstream out(tmp);
        out << partial.dump(1) << "\n";
        out.close();
        if (!out) throw Error(ErrorKind::Io, "cannot write the partial bank index", tmp.string());
    });
}

bool BankCache::mergePartialIndices(const std::vector<BankMember>& members,
                                    const std::vector<std::uint64_t>& keys, const Rect& region,
                                    const std::vector<UnavailableMember>& unavailable) {
    if (m_dir.empty()) return false;
    // Entries of every partial index of this very bank (same input, options and region); a
    // partial index of another bank, or one being replaced, is passed over.
    // Seeded with what this cache already holds: the members of an index.json written by an
    // earlier completion (so that a part run after it, even an empty one, completes again
    // instead of leaving its partial index behind) and the members this part computed.
    std::map<std::uint64_t, Entry> found;
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        for (const auto& [key, entry] : m_entries) found[key] = entry;
    }
    std::vector<fs::path> partials;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(m_dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind(kPartialPrefix, 0) != 0 || entry.path().extension() != ".json") continue;
        std::ifstream in(entry.path());
        try {
            const std::string text{std::istreambuf_iterator<char>(in), {}};
            const JsonReader r(entry.path().string());
            const json j = parseJsonText(text, r.file());
            if (readInputHash(r, j) != m_inputHash || r.at(j, "options", "") != optionsJson() ||
                r.at(j, "region", "") != regionJson(region))
                continue;
            for (const auto& [key, e] : readEntries(r, j)) found[key] = {e.first, e.second};
            partials.push_back(entry.path());
        } catch (const Error&) {
            continue;
        }
    }
    // Every member's result must be there, as a file.
    for (std::uint64_t key : keys) {
        const auto it = found.find(key);
        if (it == found.end() || !fs::exists(m_dir / it->second.file, ec)) return false;
    }
    {
        const std::lock_guard<std::mutex> lock(m_mutex);
        for (const auto& [key, entry] : found) m_entries[key] = entry;
    }
    writeIndex(members, keys, region, unavailable);
    for (const fs::path& p : partials) fs::remove(p, ec);
    return true;
}

void BankCache::writeIndex(const std::vector<BankMember>& members,
                           const std::vector<std::uint64_t>& keys, const Rect& region,
                           const std::vector<UnavailableMember>& unavailable) {
    if (m_dir.empty()) return;
    json list = json::array();
    for (std::size_t i = 0; i < members.size(); ++i) {
        const Entry& e = m_entries.at(keys[i]);
        list.push_back({{"filter", members[i].filter},
                        {"version", std::string(findFilter(members[i].filter).version())},
                        {"params", detail::paramsJson(members[i].params)},
                        {"default", members[i].isDefault},
                        {"key", toHex(keys[i])},
                        {"file", e.file},
                        {"checksum", toHex(e.checksum)}});
    }
    const json options = optionsJson();
    json index{{"format", kIndexFormat}, {"inputHash", toHex(m_inputHash)}, {"width", m_width},
               {"height", m_height},     {"region", regionJson(region)},    {"options", options},
               {"members", list}};
    // Members the options name that did not run in the process that wrote the index (a reader
    // recomputes what it can: availability is the reader's, not the folder's).
    if (!unavailable.empty()) {
        json left = json::array();
        for (const UnavailableMember& u : unavailable)
            left.push_back({{"filter", u.member.filter},
                            {"params", detail::paramsJson(u.member.params)},
                            {"reason", u.reason}});
        index["unavailable"] = left;
    }
    writeAtomically(m_dir / kIndexName, [&](const fs::path& tmp) {
        std::ofstream out(tmp);
        out << index.dump(1) << "\n";
        out.close();
        if (!out) throw Error(ErrorKind::Io, "cannot write the bank index", tmp.string());
    });
    // Member files the index no longer names (another input, other settings) go.
    std::map<std::string, bool> keep;
    for (std::size_t i = 0; i < members.size(); ++i) keep[m_entries.at(keys[i]).file] = true;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(m_dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("m-", 0) == 0 && entry.path().extension() == ".exr" && !keep.count(name))
            fs::remove(entry.path(), ec);
    }
    removeStaleTemporaries();
}

void BankCache::removeStaleTemporaries() const {
    if (m_dir.empty()) return;
    const auto now = fs::file_time_type::clock::now();
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(m_dir, ec)) {
        const long owner = bankTemporaryOwner(entry.path().filename().string());
        if (owner == 0 || !processEnded(owner)) continue;
        const auto written = entry.last_write_time(ec);
        if (ec || std::chrono::duration<double>(now - written).count() < kStaleTemporarySeconds)
            continue;
        fs::remove(entry.path(), ec);
    }
}

}  // namespace detail

BankOptions readBankOptions(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, "bank folder not found", dir.string());
    const fs::path index = dir / detail::kIndexName;
    if (!fs::exists(index, ec))
        throw Error(ErrorKind::Io,
                    "no index.json: not a bank folder (make one with glint-denoise bank)",
                    dir.string());
    const detail::JsonReader r(index.string());
    const json j = detail::parseJsonText(detail::readJsonText(index, "bank index"), r.file());
    detail::readInputHash(r, j);
    const json& o = r.at(j, "options", "");
    BankOptions options;
    options.size = int(r.integer(r.at(o, "size", "/options"), "/options/size", 1, kMaxBankSize));
    options.seed =
        r.unsignedInteger(r.at(o, "seed", "/options"), "/options/seed", std::uint64_t(INT64_MAX));
    const json& filters = r.array(r.at(o, "filters", "/options"), "/options/filters");
    for (std::size_t i = 0; i < filters.size(); ++i)
        options.filters.push_back(r.string(filters[i], "/options/filters/" + std::to_string(i)));
    // Fixed parameters of filters (absent from folders written before they existed).
    if (o.contains("filterParams")) {
        const json& fixed = o["filterParams"];
        if (!fixed.is_object()) r.fail("/options/filterParams", "expected an object");
        for (const auto& item : fixed.items())
            options.filterParams[item.key()] =
                r.params(item.value(), "/options/filterParams/" + item.key());
    }
    options.prefilter = r.boolean(r.at(o, "prefilter", "/options"), "/options/prefilter");
    const json& params = r.at(o, "prefilterParams", "/options");
    if (!params.is_object()) r.fail("/options/prefilterParams", "expected an object");
    for (const auto& item : params.items())
        options.prefilterParams[item.key()] =
            r.number(item.value(), "/options/prefilterParams/" + item.key(), -1e30, 1e30);
    const json& region = r.at(o, "region", "/options");
    if (!region.is_null()) {
        r.array(region, "/options/region", 4);
        int v[4];
        for (int i = 0; i < 4; ++i)
            v[i] = int(r.integer(region[std::size_t(i)], "/options/region/" + std::to_string(i), 0,
                                 1 << 24));
        options.region = Rect{v[0], v[1], v[2], v[3]};
    }
    // The options must be ones a build accepts (filters registered, region not empty...).
    try {
        validate(options);
    } catch (const Error& e) {
        r.fail("/options", e.message());
    }
    options.cacheDir = dir;
    return options;
}

FilterBank openBank(const FrameBuffers& frame, const fs::path& dir, const ProgressFn& progress) {
    BankOptions options = readBankOptions(dir);
    std::ifstream in(dir / detail::kIndexName);
    const json j = json::parse(in, nullptr, false);
    const std::uint64_t hash = hashFrame(frame);
    std::string stored;
    if (j.is_object() && j.contains("inputHash") && j["inputHash"].is_string())
        stored = j["inputHash"].get<std::string>();
    if (stored != detail::toHex(hash))
        throw Error(ErrorKind::Format,
                    "the folder holds the bank of another image (input hash " + stored +
                        ", this image " + detail::toHex(hash) +
                        "); build one with glint-denoise bank",
                    dir.string());
    options.progress = progress;
    // Opening reads: nothing in the folder is written (it may be on a read-only mount).
    return detail::buildBank(frame, options, detail::CacheMode::ReadOnly);
}

}  // namespace glint::denoise
