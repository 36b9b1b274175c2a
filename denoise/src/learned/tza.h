// Reader of Open Image Denoise's weight blobs (.tza, version 2): named tensors of fp16 or fp32
// values in "oihw" (convolution weights) or "x" (biases) layout, returned as fp32.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace glint::denoise::learned {

/// One tensor of a weight blob, converted to fp32.
struct TzaTensor {
    std::vector<int> shape;  ///< e.g. {out, in, 3, 3} for "oihw", {out} for "x"
    std::string layout;      ///< "oihw" or "x"
    std::vector<float> data;
};

/// Tensors by name ("enc_conv0.weight", "enc_conv0.bias", ...).
using TzaTensors = std::map<std::string, TzaTensor>;

/// Parses a weight blob held in memory. Every offset and size is checked against the blob: a
/// truncated or corrupt blob throws glint::Error(Format) naming `file` and the byte offset.
TzaTensors parseTza(const std::vector<std::uint8_t>& blob, const std::string& file);

/// IEEE 754 binary16 → binary32 (exact).
float halfToFloat(std::uint16_t h);

}  // namespace glint::denoise::learned
