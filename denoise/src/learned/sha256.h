// SHA-256 (FIPS 180-4) of a byte buffer, to check that a weight file is the one expected.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace glint::denoise::learned {

/// Lower-case hexadecimal SHA-256 digest of `data`.
std::string sha256Hex(const std::vector<std::uint8_t>& data);

}  // namespace glint::denoise::learned
