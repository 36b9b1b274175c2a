// glint-image sub-commands. Each throws glint::Error on bad input; main() reports it.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace glint::cli {

/// Options of `glint-image info`.
struct InfoOptions {
    std::string file;
    bool json = false;
};

/// Options of `glint-image diff`.
struct DiffOptions {
    std::string file;
    std::string reference;
    /// Metrics to print, each "NAME" or an expectation "NAME>=X", "NAME<=X", "mc[:ALPHA]"
    /// (--metric and its second name --expect are one option).
    std::vector<std::string> metrics;
    std::string errorMap;  ///< FLIP error map PNG, or empty
    std::string crop;      ///< "x0,x1,y0,y1" or empty
    bool linear = false;
    float exposure = 0.0f;
    bool json = false;
};

/// Options of `glint-image convert`.
struct ConvertOptions {
    std::string input;
    std::string output;
    float exposure = 0.0f;
    std::string layer;       ///< layer ("albedo") or channel ("albedo.G"); empty = colour
    std::string falseColor;  ///< "lo,hi" or empty
};

/// Options of `glint-image merge`.
struct MergeOptions {
    std::vector<std::string> shards;  ///< shards and partial merges
    std::string output;
    bool partial = false;  ///< write a partial merge of a contiguous range (re-mergeable)
    bool json = false;
};

/// Prints size, layers, metadata and non-finite counts of an image.
void runInfo(const InfoOptions& options);
/// Prints one metric of an image against a reference.
int runDiff(const DiffOptions& options);
/// Writes a layer or channel of an image as an 8-bit sRGB PNG.
void runConvert(const ConvertOptions& options);
/// Merges the shards of a sharded render (glint-render --shard i/N) into the whole frame, or a
/// contiguous range of them into a partial merge (--partial) that a later merge accepts.
void runMerge(const MergeOptions& options);

}  // namespace glint::cli
