#include "bank/bank_cache.h"

#include <bit>
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
    return h;
}

json regionJson(const Rect& r) {
    return json::array({r.x0, r.x1, r.y0, r.y1});
}

}  // namespace

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
        const json j = json::parse(in);
        if (j.at("format").get<int>() > kIndexFormat) return;
        if (fromHex(j.at("inputHash").get<std::string>()) != m_inputHash) return;
        for (const json& m : j.at("members"))
            m_entries[fromHex(m.at("key").get<std::string>())] = {
                m.at("file").get<std::string>(), fromHex(m.at("checksum").get<std::string>())};
    } catch (const std::exception&) {
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
                                    const std::vector<std::uint64_t>& keys, const Rect& region) {
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
            const json j = json::parse(in);
            if (j.at("format").get<int>() != kIndexFormat ||
                fromHex(j.at("inputHash").get<std::string>()) != m_inputHash ||
                j.at("options") != optionsJson() || j.at("region") != regionJson(region))
                continue;
            for (const json& m : j.at("members"))
                found[fromHex(m.at("key").get<std::string>())] = {
                    m.at("file").get<std::string>(), fromHex(m.at("checksum").get<std::string>())};
            partials.push_back(entry.path());
        } catch (const std::exception&) {
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
    writeIndex(members, keys, region);
    for (const fs::path& p : partials) fs::remove(p, ec);
    return true;
}

void BankCache::writeIndex(const std::vector<BankMember>& members,
                           const std::vector<std::uint64_t>& keys, const Rect& region) {
    if (m_dir.empty()) return;
    json list = json::array();
    for (std::size_t i = 0; i < members.size(); ++i) {
        const Entry& e = m_entries.at(keys[i]);
        list.push_back({{"filter", members[i].filter},
                        {"version", std::string(findFilter(members[i].filter).version())},
                        {"params", members[i].params},
                        {"default", members[i].isDefault},
                        {"key", toHex(keys[i])},
                        {"file", e.file},
                        {"checksum", toHex(e.checksum)}});
    }
    const json options = optionsJson();
    const json index{
        {"format", kIndexFormat}, {"inputHash", toHex(m_inputHash)}, {"width", m_width},
        {"height", m_height},     {"region", regionJson(region)},    {"options", options},
        {"members", list}};
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
}

}  // namespace detail

BankOptions readBankOptions(const fs::path& dir) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw Error(ErrorKind::Io, "bank folder not found", dir.string());
    const fs::path index = dir / detail::kIndexName;
    std::ifstream in(index);
    if (!in)
        throw Error(ErrorKind::Io,
                    "no index.json: not a bank folder (make one with glint-denoise bank)",
                    dir.string());
    json j;
    try {
        j = json::parse(in);
    } catch (const json::parse_error& e) {
        throw Error(ErrorKind::Format, std::string("malformed JSON: ") + e.what(), index.string());
    }
    try {
        if (j.at("format").get<int>() > detail::kIndexFormat)
            throw Error(ErrorKind::Format,
                        "index format " + std::to_string(j.at("format").get<int>()) +
                            " is newer than this Glint reads (" +
                            std::to_string(detail::kIndexFormat) + ")",
                        index.string());
        const json& o = j.at("options");
        BankOptions options;
        options.size = o.at("size").get<int>();
        options.seed = o.at("seed").get<std::uint64_t>();
        options.filters = o.at("filters").get<std::vector<std::string>>();
        options.prefilter = o.at("prefilter").get<bool>();
        options.prefilterParams = o.at("prefilterParams").get<ParamValues>();
        if (!o.at("region").is_null()) {
            const auto r = o.at("region").get<std::vector<int>>();
            if (r.size() != 4) throw Error(ErrorKind::Format, "region must have 4 numbers");
            options.region = Rect{r[0], r[1], r[2], r[3]};
        }
        options.cacheDir = dir;
        return options;
    } catch (const Error& e) {
        throw Error(ErrorKind::Format, e.message(), index.string());
    } catch (const json::exception& e) {
        throw Error(ErrorKind::Format, std::string("unexpected index content: ") + e.what(),
                    index.string());
    }
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
    return buildBank(frame, options);
}

}  // namespace glint::denoise
