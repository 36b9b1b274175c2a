// Tiled, MIP-mapped EXR textures written for the texture tests, as maketx would write them.
#pragma once

#include <filesystem>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gtest/gtest.h>

namespace glint::render::test {

/// Writes `image` as a tiled (64² tiles), MIP-mapped EXR with box-filtered levels.
inline void writeTiledTexture(const OIIO::ImageBuf& image, const std::filesystem::path& file) {
    OIIO::ImageSpec config;
    config.tile_width = config.tile_height = 64;
    config.attribute("maketx:filtername", "box");
    ASSERT_TRUE(OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, image,
                                                 file.string(), config))
        << OIIO::geterror();
}

/// Writes a `size`² checkerboard of `square`-texel squares (1 and 0, RGB float).
inline void writeCheckerTexture(const std::filesystem::path& file, int size, int square) {
    OIIO::ImageBuf checker(OIIO::ImageSpec(size, size, 3, OIIO::TypeDesc::FLOAT));
    const float white[3] = {1.0f, 1.0f, 1.0f}, black[3] = {0.0f, 0.0f, 0.0f};
    OIIO::ImageBufAlgo::checker(checker, square, square, 1, white, black);
    writeTiledTexture(checker, file);
}

}  // namespace glint::render::test
