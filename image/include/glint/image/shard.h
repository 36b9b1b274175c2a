// Sharded renders (docs/distributed.md): what a shard records about itself, and the exact merge
// of a complete set of shards into the frame one machine renders with the same seed and spp.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "glint/image/frame_buffers.h"

namespace glint {

/// Where a frame sits in a sharded render (glint-render --shard i/N). Stored as glint:*
/// attributes: glint:shard "i/N", glint:shardSamples "begin end", glint:shardTotalSpp and
/// glint:sceneHash (16 hex digits).
struct ShardInfo {
    int index = 0;        ///< i, 0-based
    int count = 1;        ///< N
    int totalSpp = 0;     ///< spp of the whole render
    int sampleBegin = 0;  ///< per-pixel sample indices [sampleBegin, sampleEnd) of this shard
    int sampleEnd = 0;
    std::uint64_t sceneHash = 0;  ///< content hash of the scene rendered
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

/// Merges a complete set of shards of one render into the frame one machine renders with the
/// same seed and total spp: per pixel and channel, the means, variances of the mean and counts
/// are combined with the parallel form of Welford's update (Chan, Golub and LeVeque 1979), in
/// double, shards taken in index order (so any argument order gives the same bits). Pixels
/// weigh by their own sample counts, so a shard of a cancelled render merges correctly.
/// Throws Error(InvalidArgument) naming the shards when the set has a missing, duplicated or
/// foreign shard (other scene, seed, N, spp, sampler, integrator, size or layers), or a frame
/// that is no shard. Accuracy (docs/distributed.md, "Exactness"): each merged mean is within
/// 4 ulps of the largest shard mean of its pixel and channel of the single render.
FrameBuffers mergeShards(std::vector<ShardFrame> shards);

}  // namespace glint
