// Shard metadata and the exact merge of a sharded render (docs/distributed.md).
#include "glint/image/shard.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "glint/image/error.h"

namespace glint {

namespace {

// glint:* keys a shard adds to its frame (FrameMetadata::extra, without the prefix).
constexpr const char* kShardKey = "shard";
constexpr const char* kSamplesKey = "shardSamples";
constexpr const char* kTotalSppKey = "shardTotalSpp";
constexpr const char* kSceneHashKey = "sceneHash";

/// Parses the whole of `text` as an integer; nullopt when it is not one.
template <typename T>
std::optional<T> parseWhole(std::string_view text, int base = 10) {
    T value{};
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, base);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
    return value;
}

/// Parses "a<sep>b" as two integers.
std::optional<std::pair<int, int>> parsePair(const std::string& text, char sep) {
    const std::size_t at = text.find(sep);
    if (at == std::string::npos) return std::nullopt;
    const auto a = parseWhole<int>(std::string_view(text).substr(0, at));
    const auto b = parseWhole<int>(std::string_view(text).substr(at + 1));
    if (!a || !b) return std::nullopt;
    return std::pair{*a, *b};
}

std::string shardName(const ShardInfo& s) {
    return std::to_string(s.index) + "/" + std::to_string(s.count);
}

/// The metadata two shards of one render share: everything but what differs per shard.
std::map<std::string, std::string> renderIdentity(const FrameBuffers& frame) {
    const FrameMetadata& md = frame.metadata();
    std::map<std::string, std::string> id(md.extra.begin(), md.extra.end());
    for (const char* key : {kShardKey, kSamplesKey, "cancelled"}) id.erase(key);
    if (const auto shard = md.extra.find(kShardKey); shard != md.extra.end())
        id["N"] = shard->second.substr(shard->second.find('/') + 1);
    id["seed"] = std::to_string(md.seed);
    id["integrator"] = md.integrator;
    id["size"] = std::to_string(frame.width()) + "x" + std::to_string(frame.height());
    std::string layers;
    for (int l = 0; l < kLayerCount; ++l)
        if (frame.has(Layer(l))) layers += std::string(layerDisplayName(Layer(l))) + " ";
    id["layers"] = layers;
    return id;
}

/// First difference between two identities, as "key a vs b" (empty when equal).
std::string firstDifference(const std::map<std::string, std::string>& a,
                            const std::map<std::string, std::string>& b) {
    auto show = [](const std::map<std::string, std::string>& m, const std::string& key) {
        const auto it = m.find(key);
        return it == m.end() ? std::string("(none)") : "'" + it->second + "'";
    };
    for (const auto& [key, value] : a)
        if (show(b, key) != "'" + value + "'")
            return key + " " + show(b, key) + " vs " + show(a, key);
    for (const auto& [key, value] : b)
        if (!a.count(key)) return key + " '" + value + "' vs (none)";
    return {};
}

/// Running (count, mean, M2) of one channel (Chan, Golub and LeVeque 1979).
struct Moments {
    double n = 0.0, mean = 0.0, m2 = 0.0;

    /// Adds a group of `nb` samples with mean `meanB` and sum of squared deviations `m2B`.
    void add(double nb, double meanB, double m2B) {
        if (nb <= 0.0) return;
        const double total = n + nb;
        const double delta = meanB - mean;
        // Chan et al. 1979, eq. 2.1: M2 = M2_A + M2_B + delta^2 n_A n_B / n.
        mean += delta * (nb / total);
        m2 += m2B + delta * delta * (n * nb / total);
        n = total;
    }
};

}  // namespace

std::pair<int, int> shardSampleRange(int spp, int index, int count) {
    const auto at = [&](int i) { return int(std::int64_t(i) * spp / count); };
    return {at(index), at(index + 1)};
}

std::pair<int, int> parseShardSpec(const std::string& text, const std::string& where) {
    const auto pair = parsePair(text, '/');
    if (!pair || pair->second < 1 || pair->first < 0 || pair->first >= pair->second)
        throw Error(ErrorKind::InvalidArgument,
                    "'" + text + "' is not a shard i/N with 0 <= i < N (e.g. 0/4)", "command line",
                    where);
    return *pair;
}

void setShardInfo(FrameMetadata& metadata, const ShardInfo& info) {
    char hash[17];
    std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(info.sceneHash));
    metadata.extra[kShardKey] = shardName(info);
    metadata.extra[kSamplesKey] =
        std::to_string(info.sampleBegin) + " " + std::to_string(info.sampleEnd);
    metadata.extra[kTotalSppKey] = std::to_string(info.totalSpp);
    metadata.extra[kSceneHashKey] = hash;
}

std::optional<ShardInfo> shardInfo(const FrameMetadata& metadata, const std::string& file) {
    const auto shard = metadata.extra.find(kShardKey);
    if (shard == metadata.extra.end()) return std::nullopt;
    auto get = [&](const char* key) -> const std::string& {
        const auto it = metadata.extra.find(key);
        if (it == metadata.extra.end())
            throw Error(ErrorKind::Format, "a shard must also carry glint:" + std::string(key),
                        file, std::string("attribute glint:") + key);
        return it->second;
    };
    auto bad = [&](const char* key, const std::string& expected) {
        return Error(ErrorKind::Format, "expected " + expected + ", got '" + get(key) + "'", file,
                     std::string("attribute glint:") + key);
    };
    ShardInfo info;
    const auto spec = parsePair(shard->second, '/');
    if (!spec || spec->second < 1 || spec->first < 0 || spec->first >= spec->second)
        throw bad(kShardKey, "i/N with 0 <= i < N");
    info.index = spec->first;
    info.count = spec->second;
    const auto total = parseWhole<int>(get(kTotalSppKey));
    if (!total || *total < info.count) throw bad(kTotalSppKey, "an spp of at least N");
    info.totalSpp = *total;
    const auto range = parsePair(get(kSamplesKey), ' ');
    if (!range || *range != shardSampleRange(info.totalSpp, info.index, info.count))
        throw bad(kSamplesKey, "the sample range of shard " + shardName(info) + " of " +
                                   std::to_string(info.totalSpp) + " spp");
    info.sampleBegin = range->first;
    info.sampleEnd = range->second;
    const auto hash = parseWhole<std::uint64_t>(get(kSceneHashKey), 16);
    if (!hash || get(kSceneHashKey).size() != 16) throw bad(kSceneHashKey, "16 hex digits");
    info.sceneHash = *hash;
    return info;
}

FrameBuffers mergeShards(std::vector<ShardFrame> shards) {
    if (shards.empty())
        throw Error(ErrorKind::InvalidArgument, "no shards to merge", "command line", "SHARD.exr");

    // Identify every shard, then order them by index: the merge is then the same for any
    // order of the arguments.
    std::vector<ShardInfo> infos;
    for (const ShardFrame& s : shards) {
        const auto info = shardInfo(s.frame.metadata(), s.file);
        if (!info)
            throw Error(ErrorKind::InvalidArgument,
                        "not a shard (no glint:shard attribute; render it with glint-render "
                        "--shard i/N)",
                        s.file);
        infos.push_back(*info);
    }
    std::vector<std::size_t> order(shards.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return infos[a].index < infos[b].index; });

    // Refuse a foreign shard: one of another render (scene, seed, N, spp, settings, size).
    const ShardFrame& first = shards[order[0]];
    const auto identity = renderIdentity(first.frame);
    for (std::size_t k : order) {
        const std::string diff = firstDifference(identity, renderIdentity(shards[k].frame));
        if (!diff.empty())
            throw Error(ErrorKind::InvalidArgument,
                        "shard " + shardName(infos[k]) + " is foreign to shard " +
                            shardName(infos[order[0]]) + " of " + first.file + ": " + diff,
                        shards[k].file);
    }
    // Refuse duplicates and gaps.
    const int count = infos[order[0]].count;
    for (std::size_t j = 1; j < order.size(); ++j)
        if (infos[order[j]].index == infos[order[j - 1]].index)
            throw Error(ErrorKind::InvalidArgument,
                        "shard " + shardName(infos[order[j]]) + " is given twice: " +
                            shards[order[j - 1]].file + " and " + shards[order[j]].file,
                        shards[order[j]].file);
    if (int(order.size()) != count) {
        std::string missing, have;
        std::size_t j = 0;
        for (int i = 0; i < count; ++i) {
            if (j < order.size() && infos[order[j]].index == i) {
                have += (have.empty() ? "" : ", ") + shards[order[j]].file + " (" +
                        shardName(infos[order[j]]) + ")";
                ++j;
            } else {
                missing +=
                    (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(count);
            }
        }
        throw Error(ErrorKind::InvalidArgument,
                    "incomplete shard set: missing " + missing + "; given " + have, "command line",
                    "SHARD.exr");
    }

    // The merged frame: the layers of the shards, their metadata without the shard's own.
    const int width = first.frame.width(), height = first.frame.height();
    FrameBuffers out(width, height);
    for (int l = 0; l < kLayerCount; ++l)
        if (first.frame.has(Layer(l))) out.ensure(Layer(l));
    FrameMetadata md = first.frame.metadata();
    for (const char* key : {kShardKey, kSamplesKey, kTotalSppKey, "cancelled"}) md.extra.erase(key);
    md.extra["mergedShards"] = std::to_string(count);
    md.spp = 0;
    md.nonFiniteSamples = 0;
    for (const ShardFrame& s : shards) {
        md.spp += s.frame.metadata().spp;
        md.nonFiniteSamples += s.frame.metadata().nonFiniteSamples;
        if (s.frame.metadata().extra.count("cancelled")) md.extra["cancelled"] = "true";
    }
    out.metadata() = md;

    // Each layer with its variance of the mean (M2 = var · n · (n − 1)); position has none.
    struct Pair {
        Layer mean;
        std::optional<Layer> variance;
    };
    std::vector<Pair> pairs;
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        if (layer == Layer::SampleCount || varianceOf(layer) || !out.has(layer)) continue;
        const auto var = varianceLayer(layer);
        pairs.push_back({layer, var && out.has(*var) ? var : std::nullopt});
    }
    const bool counted = out.has(Layer::SampleCount);
    if (!counted)
        throw Error(ErrorKind::InvalidArgument, "a shard must have a sampleCount layer", first.file,
                    "sampleCount");

    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& rows) {
        for (int y = rows.begin(); y != rows.end(); ++y)
            for (int x = 0; x < width; ++x) {
                double total = 0.0;
                for (std::size_t k : order)
                    total += shards[k].frame.layer(Layer::SampleCount)(x, y, 0);
                out.layer(Layer::SampleCount)(x, y, 0) = float(total);
                for (const Pair& p : pairs) {
                    const int channels = layerInfo(p.mean).channels;
                    for (int c = 0; c < channels; ++c) {
                        Moments m;
                        for (std::size_t k : order) {
                            const FrameBuffers& f = shards[k].frame;
                            const double n = f.layer(Layer::SampleCount)(x, y, 0);
                            const double var = p.variance ? f.layer(*p.variance)(x, y, c) : 0.0;
                            m.add(n, f.layer(p.mean)(x, y, c), var * n * std::max(n - 1.0, 0.0));
                        }
                        out.layer(p.mean)(x, y, c) = float(m.mean);
                        if (p.variance)
                            out.layer (*p.variance)(x, y, c) =
                                m.n > 1.0 ? float(m.m2 / (m.n * (m.n - 1.0))) : 0.0f;
                    }
                }
            }
    });
    return out;
}

}  // namespace glint
