// Sharded renders (docs/distributed.md): what a shard records about itself, and the exact merge
// of a complete set of shards into the frame one machine renders with the same seed and spp.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "glint/image/frame_buffers.h"

namespace glint {

/// Where a frame sits in a sharded render (glint-render --shard i/N), or which shards a partial
/// merge holds (glint-image merge --partial). Stored as glint:* attributes: glint:shard "i/N"
/// (a partial merge of shards a … b, inclusive: "a-b/N"), glint:shardSamples "begin end",
/// glint:shardTotalSpp and glint:sceneHash (16 hex digits).
struct ShardInfo {
    int index = 0;        ///< i (first shard held), 0-based
    int count = 1;        ///< N
    int totalSpp = 0;     ///< spp of the whole render
    int sampleBegin = 0;  ///< per-pixel sample indices [sampleBegin, sampleEnd) of this shard
    int sampleEnd = 0;
    std::uint64_t sceneHash = 0;  ///< content hash of the scene rendered
    int lastIndex = -1;           ///< last shard held by a partial merge; -1: shard `index` only

    /// The last shard this frame holds (index for a plain shard).
    int last() const { return lastIndex < 0 ? index : lastIndex; }
};

/// The per-pixel sample range of shard `index` of `count` over `spp` samples:
/// [⌊index·spp/count⌋, ⌊(index+1)·spp/count⌋). Non-empty for every index when count ≤ spp.
std::pair<int, int> shardSampleRange(int spp, int index, int count);

/// Parses "i/N" (0 ≤ i < N); throws Error(InvalidArgument) naming `where`.
std::pair<int, int> parseShardSpec(const std::string& text, const std::string& where);

/// Records `info` in the frame's metadata (the glint:* attributes above).
void setShardInfo(FrameMetadata& metadata, const ShardInfo& info);

/// The shard a frame read from `file` is, or nullopt when it carries no glint:shard. Throws
/// Error(Format) naming the file and the attribute when the shard attributes are malformed.
std::optional<ShardInfo> shardInfo(const FrameMetadata& metadata, const std::string& file);

/// A shard and the file it came from (named in messages).
struct ShardFrame {
    std::string file;
    FrameBuffers frame;
};

/// What a merge must produce from its inputs.
enum class MergeKind {
    Whole,    ///< the inputs tile shards 0 … N−1: the whole render, with no shard attributes
    Partial,  ///< the inputs tile a contiguous range a … b: a frame recording "a-b/N"
};

/// Merges shards of one render — plain shards and partial merges, together tiling every shard
/// 0 … N−1 (or, for MergeKind::Partial, a contiguous range) exactly once — into the frame one
/// machine renders with the same seed and total spp: per pixel and channel, the means,
/// variances of the mean and counts are combined with the parallel form of Welford's update
/// (Chan, Golub and LeVeque 1979), in double, inputs taken in shard order (so any argument
/// order gives the same bits). Pixels weigh by their own sample counts, so a shard of a
/// cancelled render merges correctly. Throws Error(InvalidArgument) naming the files when the
/// set has a gap, an overlap (a shard given twice) or a foreign shard (other scene, seed, N,
/// spp, sampler, integrator, size or layers), or a frame that is no shard. Accuracy
/// (docs/distributed.md, "Exactness"): each merged mean is within 4 ulps of the largest shard
/// mean of its pixel and channel of the single render; a tree of merges is within the
/// tolerance stated there of the flat merge.
FrameBuffers mergeShards(std::vector<ShardFrame> shards, MergeKind kind = MergeKind::Whole);

/// mergeShards of the files `files`, holding one of them at a time: reads and checks the
/// headers of all first (nothing is merged from a bad set), then reads and folds them one by
/// one in shard order into double accumulators. The result is bit-identical to mergeShards of
/// the same files read with readExr; peak memory is about one input plus the accumulators
/// (docs/distributed.md, "Scale"). `progress(done, total)` is called after each file is folded;
/// returning false stops the merge with Error(Cancelled).
FrameBuffers mergeShardFiles(const std::vector<std::string>& files,
                             MergeKind kind = MergeKind::Whole,
                             const std::function<bool(int, int)>& progress = {});

}  // namespace glint
