// Shard metadata and the exact merge of a sharded render (docs/distributed.md).
#include "glint/image/shard.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <string_view>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "channel_aliases.h"
#include "exr_layout.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "image_files.h"
#include "shard_accumulator.h"

namespace glint {

namespace {

// glint:* keys a shard adds to its frame (FrameMetadata::extra, without the prefix).
constexpr const char* kShardKey = "shard";
constexpr const char* kSamplesKey = "shardSamples";
constexpr const char* kTotalSppKey = "shardTotalSpp";
constexpr const char* kSceneHashKey = "sceneHash";
constexpr const char* kCancelledKey = "cancelled";
constexpr const char* kMergedKey = "mergedShards";

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
    const std::string n = "/" + std::to_string(s.count);
    if (s.last() == s.index) return std::to_string(s.index) + n;
    return std::to_string(s.index) + "-" + std::to_string(s.last()) + n;
}

/// "shard i/N" or "shards a-b/N", for messages.
std::string shardsName(const ShardInfo& s) {
    return (s.last() == s.index ? "shard " : "shards ") + shardName(s);
}

/// "i/N" or, for a range of shards, "a-b/N".
std::string rangeName(int first, int last, int count) {
    ShardInfo s;
    s.index = first;
    s.lastIndex = last;
    s.count = count;
    return shardName(s);
}

using Identity = std::map<std::string, std::string>;

/// The metadata two shards of one render share: everything but what differs per shard (its
/// place, its own spp, whether it was cancelled, how many shards a partial merge holds).
/// `layers` lists the layers present.
Identity renderIdentity(const FrameMetadata& md, int width, int height, const std::string& layers) {
    Identity id(md.extra.begin(), md.extra.end());
    for (const char* key : {kShardKey, kSamplesKey, kCancelledKey, kMergedKey}) id.erase(key);
    if (const auto shard = md.extra.find(kShardKey); shard != md.extra.end())
        id["N"] = shard->second.substr(shard->second.find('/') + 1);
    id["seed"] = std::to_string(md.seed);
    id["integrator"] = md.integrator;
    id["size"] = std::to_string(width) + "x" + std::to_string(height);
    id["layers"] = layers;
    return id;
}

std::string layerList(const FrameBuffers& frame) {
    std::string layers;
    for (int l = 0; l < kLayerCount; ++l)
        if (frame.has(Layer(l))) layers += std::string(layerDisplayName(Layer(l))) + " ";
    return layers;
}

/// First difference between two identities, as "key a vs b" (empty when equal).
std::string firstDifference(const Identity& a, const Identity& b) {
    auto show = [](const Identity& m, const std::string& key) {
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

/// What the merge checks of one input before folding its pixels.
struct Piece {
    std::string file;
    ShardInfo info;
    Identity identity;
    bool counted = false;  ///< has a sampleCount layer
};

Piece pieceOf(const std::string& file, const FrameMetadata& md, int width, int height,
              const std::string& layers, bool counted) {
    const auto info = shardInfo(md, file);
    if (!info)
        throw Error(ErrorKind::InvalidArgument,
                    "not a shard (no glint:shard attribute; render it with glint-render "
                    "--shard i/N)",
                    file);
    return {file, *info, renderIdentity(md, width, height, layers), counted};
}

Piece pieceOf(const std::string& file, const FrameBuffers& frame) {
    return pieceOf(file, frame.metadata(), frame.width(), frame.height(), layerList(frame),
                   frame.has(Layer::SampleCount));
}

/// The Piece of an EXR from its header alone (no pixels read): the same glint:* attributes and
/// layers readExr gives (mergeShardFiles checks both agree once it reads the pixels).
Piece readPieceHeader(const std::string& file) {
    detail::ExrInput in(file);
    const detail::ExrLayout& layout = in.layout();
    FrameMetadata md;
    bool glint = false;
    for (const detail::ExrAttribute& a : layout.attributes) {
        const std::string& name = a.name;
        if (name.rfind("glint:", 0) != 0) continue;
        glint = true;
        const std::string key = name.substr(6), value = a.text;
        if (key == "integrator") {
            md.integrator = value;
        } else if (key == "seed") {
            const auto seed = a.integer ? std::optional(std::uint64_t(*a.integer))
                                        : parseWhole<std::uint64_t>(value);
            if (!seed)
                throw Error(ErrorKind::Format, "expected an integer, got '" + value + "'", file,
                            "attribute glint:seed");
            md.seed = *seed;
        } else if (key != "spp" && key != "scene" && key != "varianceOf" && key != "normalSpace" &&
                   key != "depth" && key != "nonFiniteSamples") {
            md.extra[key] = value;
        }
    }
    const detail::ChannelPlan plan = detail::planChannels(layout.channelNames, glint, file);
    std::vector<bool> present(kLayerCount, false);
    for (const detail::LayerSource& src : plan.layers) present[int(src.layer)] = true;
    std::string layers;
    for (int l = 0; l < kLayerCount; ++l)
        if (present[l]) layers += std::string(layerDisplayName(Layer(l))) + " ";
    return pieceOf(file, md, layout.width, layout.height, layers, present[int(Layer::SampleCount)]);
}

/// Up to `limit` items of `items` joined by ", ", then "and K more".
std::string joinShort(const std::vector<std::string>& items, std::size_t limit = 8) {
    std::string out;
    for (std::size_t i = 0; i < items.size() && i < limit; ++i) out += (i ? ", " : "") + items[i];
    if (items.size() > limit) out += ", and " + std::to_string(items.size() - limit) + " more";
    return out;
}

/// Checks that `pieces` are of one render and tile shards 0 … N−1 (Whole) or a contiguous range
/// (Partial) exactly once; returns their order by first shard. Throws naming the files.
std::vector<std::size_t> checkSet(const std::vector<Piece>& pieces, MergeKind kind) {
    if (pieces.empty())
        throw Error(ErrorKind::InvalidArgument, "no shards to merge", "command line", "SHARD.exr");
    std::vector<std::size_t> order(pieces.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        return pieces[a].info.index < pieces[b].info.index;
    });

    // Refuse a foreign shard: one of another render (scene, seed, N, spp, settings, size).
    const Piece& first = pieces[order[0]];
    for (std::size_t k : order) {
        const std::string diff = firstDifference(first.identity, pieces[k].identity);
        if (!diff.empty())
            throw Error(ErrorKind::InvalidArgument,
                        "shard " + shardName(pieces[k].info) + " is foreign to shard " +
                            shardName(first.info) + " of " + first.file + ": " + diff,
                        pieces[k].file);
    }
    // Refuse overlaps: a shard held by two inputs.
    std::size_t reach = order[0];  // the input reaching furthest so far
    for (std::size_t j = 1; j < order.size(); ++j) {
        const Piece& p = pieces[order[j]];
        const Piece& q = pieces[reach];
        if (p.info.index <= q.info.last()) {
            if (p.info.last() == p.info.index && q.info.last() == q.info.index)
                throw Error(
                    ErrorKind::InvalidArgument,
                    "shard " + shardName(p.info) + " is given twice: " + q.file + " and " + p.file,
                    p.file);
            throw Error(ErrorKind::InvalidArgument,
                        shardsName(p.info) + " overlaps " + shardsName(q.info) + " of " + q.file +
                            " (shard " + std::to_string(p.info.index) + " is held twice)",
                        p.file);
        }
        if (p.info.last() > q.info.last()) reach = order[j];
    }
    // Refuse gaps: at the ends for a whole merge, between the inputs for both kinds.
    const int count = first.info.count;
    std::vector<std::string> missing, given;
    int next = kind == MergeKind::Whole ? 0 : first.info.index;
    for (std::size_t k : order) {
        const Piece& p = pieces[k];
        if (p.info.index > next) missing.push_back(rangeName(next, p.info.index - 1, count));
        given.push_back(p.file + " (" + shardName(p.info) + ")");
        next = p.info.last() + 1;
    }
    if (kind == MergeKind::Whole && next < count)
        missing.push_back(rangeName(next, count - 1, count));
    if (!missing.empty())
        throw Error(ErrorKind::InvalidArgument,
                    std::string(kind == MergeKind::Whole
                                    ? "incomplete shard set: missing "
                                    : "the shards of a partial merge must be a contiguous "
                                      "range: missing ") +
                        joinShort(missing) + "; given " + joinShort(given),
                    "command line", "SHARD.exr");
    if (!first.counted)
        throw Error(ErrorKind::InvalidArgument, "a shard must have a sampleCount layer", first.file,
                    "sampleCount");
    return order;
}

/// Refuses a pixel no render writes before it enters a merge, where it would spread into the
/// merged means and variances without a word: a sample count that is not a whole number in
/// [0, the samples the shard holds], a half count above its pixel's count, a non-finite value,
/// a negative variance. Names the file, the layer and the first such pixel in row order.
void checkShardPixels(const FrameBuffers& f, const Piece& piece) {
    const float maxCount = float(piece.info.sampleEnd - piece.info.sampleBegin);
    const Image& counts = f.layer(Layer::SampleCount);
    /// The largest value channel values of `layer` at (x, y) may take (+inf: no bound).
    auto countBound = [&](Layer layer, int x, int y) {
        return layer == Layer::SampleCount ? maxCount : counts(x, y, 0);
    };
    auto ok = [&](Layer layer, float v, int x, int y) {
        if (!std::isfinite(v)) return false;
        if (layer == Layer::SampleCount || layer == Layer::HalfSampleCount)
            return v >= 0.0f && v == std::floor(v) && v <= countBound(layer, x, y);
        return v >= 0.0f || !varianceOf(layer);
    };
    // The first bad pixel by row: rows are checked in parallel, the lowest bad row wins.
    const int width = f.width(), height = f.height();
    auto rowOk = [&](int y) {
        for (int l = 0; l < kLayerCount; ++l)
            if (const Image* im = f.find(Layer(l)))
                for (int x = 0; x < width; ++x)
                    for (int c = 0; c < im->channels(); ++c)
                        if (!ok(Layer(l), (*im)(x, y, c), x, y)) return false;
        return true;
    };
    std::atomic<int> firstBad{height};
    tbb::parallel_for(tbb::blocked_range<int>(0, height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y != r.end() && y < firstBad.load(); ++y) {
            if (rowOk(y)) continue;
            int seen = firstBad.load();
            while (y < seen && !firstBad.compare_exchange_weak(seen, y)) {
            }
            return;
        }
    });
    const int y = firstBad.load();
    for (int x = 0; y < height && x < width; ++x)
        for (int l = 0; l < kLayerCount; ++l) {
            const Image* im = f.find(Layer(l));
            for (int c = 0; im && c < im->channels(); ++c) {
                const float v = (*im)(x, y, c);
                if (ok(Layer(l), v, x, y)) continue;
                const bool count =
                    Layer(l) == Layer::SampleCount || Layer(l) == Layer::HalfSampleCount;
                char value[32];
                std::snprintf(value, sizeof value, "%g", double(v));
                throw Error(ErrorKind::Format,
                            "corrupt shard pixel: " + std::string(value) +
                                (count ? "; expected a whole sample count in [0, " +
                                             std::to_string(int(countBound(Layer(l), x, y))) + "]"
                                 : !std::isfinite(v) ? "; expected a finite value"
                                                     : "; expected a variance >= 0") +
                                " (nothing was merged)",
                            piece.file,
                            "pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") " +
                                channelName(Layer(l), c));
            }
        }
}

/// The metadata of a merge: that of the first input in shard order, the sums of the inputs'
/// spp and non-finite samples, and the range held (Partial) or no shard attributes (Whole).
struct MergedMetadata {
    FrameMetadata md;
    bool started = false;

    void add(const FrameMetadata& input) {
        if (!started) {
            md = input;
            md.spp = 0;
            md.nonFiniteSamples = 0;
            for (const char* key : {kShardKey, kSamplesKey, kTotalSppKey, kCancelledKey})
                md.extra.erase(key);
            started = true;
        }
        md.spp += input.spp;
        md.nonFiniteSamples += input.nonFiniteSamples;
        if (input.extra.count(kCancelledKey)) md.extra[kCancelledKey] = "true";
    }

    FrameMetadata finish(const std::vector<Piece>& pieces, const std::vector<std::size_t>& order,
                         MergeKind kind) const {
        FrameMetadata out = md;
        const ShardInfo& first = pieces[order.front()].info;
        const int last = pieces[order.back()].info.last();
        out.extra[kMergedKey] = std::to_string(last - first.index + 1);
        if (kind == MergeKind::Partial) {
            ShardInfo range = first;
            range.lastIndex = last;
            range.sampleBegin = shardSampleRange(first.totalSpp, first.index, first.count).first;
            range.sampleEnd = shardSampleRange(first.totalSpp, last, first.count).second;
            setShardInfo(out, range);
        }
        return out;
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
    // "i/N", or "a-b/N" for a partial merge of shards a … b.
    const std::string& text = shard->second;
    const auto spec = parsePair(text, '/');
    const std::size_t dash = text.find('-');
    const bool ranged = dash != std::string::npos && dash < text.find('/');
    int first = spec ? spec->first : -1, last = first, count = spec ? spec->second : 0;
    if (ranged) {
        const auto a = parseWhole<int>(std::string_view(text).substr(0, dash));
        const auto slashAt = text.find('/');
        const auto b = parseWhole<int>(std::string_view(text).substr(dash + 1, slashAt - dash - 1));
        count = parseWhole<int>(std::string_view(text).substr(slashAt + 1)).value_or(0);
        first = a.value_or(-1);
        last = b.value_or(-1);
    }
    if (count < 1 || first < 0 || last < first || last >= count)
        throw bad(kShardKey, "i/N with 0 <= i < N, or a-b/N with 0 <= a <= b < N");
    info.index = first;
    info.count = count;
    if (last != first) info.lastIndex = last;
    const auto total = parseWhole<int>(get(kTotalSppKey));
    if (!total || *total < info.count) throw bad(kTotalSppKey, "an spp of at least N");
    info.totalSpp = *total;
    const auto samples = parsePair(get(kSamplesKey), ' ');
    const std::pair<int, int> expected{
        shardSampleRange(info.totalSpp, info.index, info.count).first,
        shardSampleRange(info.totalSpp, info.last(), info.count).second};
    if (!samples || *samples != expected)
        throw bad(kSamplesKey, "the sample range of shard " + shardName(info) + " of " +
                                   std::to_string(info.totalSpp) + " spp");
    info.sampleBegin = samples->first;
    info.sampleEnd = samples->second;
    const auto hash = parseWhole<std::uint64_t>(get(kSceneHashKey), 16);
    if (!hash || get(kSceneHashKey).size() != 16) throw bad(kSceneHashKey, "16 hex digits");
    info.sceneHash = *hash;
    return info;
}

FrameBuffers mergeShards(std::vector<ShardFrame> shards, MergeKind kind) {
    std::vector<Piece> pieces;
    for (const ShardFrame& s : shards) pieces.push_back(pieceOf(s.file, s.frame));
    const std::vector<std::size_t> order = checkSet(pieces, kind);
    for (std::size_t k : order) checkShardPixels(shards[k].frame, pieces[k]);
    detail::ShardAccumulator sum(shards[order[0]].frame);
    MergedMetadata md;
    for (std::size_t k : order) {
        sum.add(shards[k].frame);
        md.add(shards[k].frame.metadata());
    }
    return sum.finish(md.finish(pieces, order, kind));
}

FrameBuffers mergeShardFiles(const std::vector<std::string>& files, MergeKind kind,
                             const std::function<bool(int, int)>& progress) {
    // Check the whole set from the headers before reading any pixels.
    std::vector<Piece> pieces;
    for (const std::string& file : files) pieces.push_back(readPieceHeader(file));
    const std::vector<std::size_t> order = checkSet(pieces, kind);

    // Fold the inputs one at a time, in shard order.
    std::optional<detail::ShardAccumulator> sum;
    MergedMetadata md;
    int done = 0;
    for (std::size_t k : order) {
        const FrameBuffers frame = readExr(files[k]);
        const Piece read = pieceOf(files[k], frame);
        const std::string diff = firstDifference(pieces[k].identity, read.identity);
        if (!diff.empty() || shardName(read.info) != shardName(pieces[k].info))
            throw Error(ErrorKind::Format,
                        "the file changed while merging (header read before: shard " +
                            shardName(pieces[k].info) + "; now: shard " + shardName(read.info) +
                            (diff.empty() ? "" : ", " + diff) + ")",
                        files[k]);
        checkShardPixels(frame, read);
        if (!sum) sum.emplace(frame);
        sum->add(frame);
        md.add(frame.metadata());
        if (progress && !progress(++done, int(order.size())))
            throw Error(ErrorKind::Cancelled, "merge cancelled", files[k]);
    }
    return sum->finish(md.finish(pieces, order, kind));
}

}  // namespace glint
