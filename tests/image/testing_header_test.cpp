// Tests of glint/image/testing.h, the installed GoogleTest-friendly image assertions: on files
// written here, passing and failing expectations, bad input as a failed match.
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "glint/image/frame_buffers.h"
#include "glint/image/io.h"
#include "glint/image/testing.h"

namespace testing_header {

struct Files {
    std::filesystem::path dir, image, reference, missing;
};

/// A reference EXR and an image 1 % brighter, both with variance layers (1e-4 per value).
Files writeFiles() {
    Files f;
    f.dir = std::filesystem::temp_directory_path() /
            ("glint-testing-header-" + std::to_string(::getpid()));
    std::filesystem::create_directories(f.dir);
    f.image = f.dir / "image.exr";
    f.reference = f.dir / "reference.exr";
    f.missing = f.dir / "missing.exr";
    for (const bool brighter : {false, true}) {
        glint::FrameBuffers frame(32, 32);
        glint::Image& color = frame.color();
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x)
                for (int c = 0; c < 3; ++c)
                    color(x, y, c) =
                        float((0.2 + 0.02 * ((x + y + c) % 20)) * (brighter ? 1.01 : 1.0));
        frame.set(glint::Layer::Variance, glint::Image(32, 32, 3, 1e-4f));
        glint::writeExr(frame, brighter ? f.image : f.reference);
    }
    return f;
}

}  // namespace testing_header

TEST(TestingHeader, MacrosPassAndFailWithGlintsMessage) {
    const testing_header::Files f = testing_header::writeFiles();
    const std::string image = f.image.string(), reference = f.reference.string();
    // A 1 % difference everywhere: SSIM and PSNR pass, but it is a bias, not noise (z = 0.0035 /
    // 0.014 on every value, 3072 values), and the Monte Carlo comparison says so.
    GLINT_EXPECT_IMAGE_MATCHES(image, reference, "ssim>=0.99", "psnr>=35");
    EXPECT_NONFATAL_FAILURE(GLINT_EXPECT_IMAGE_MATCHES(image, reference, "ssim>=0.99", "mc"),
                            "differs by 1 %");
    GLINT_ASSERT_IMAGE_MATCHES(image, reference, "relmse<=1e-3");
    EXPECT_NONFATAL_FAILURE(GLINT_EXPECT_IMAGE_MATCHES(image, reference, "mse<=1e-9"), "mse 1.");
    EXPECT_NONFATAL_FAILURE(GLINT_EXPECT_IMAGE_MATCHES(f.missing.string(), reference, "ssim>=0.9"),
                            "missing.exr");
    const glint::testing::ImageMatch bad =
        glint::testing::imagesMatch(image, reference, {"ssim=0.9"});
    EXPECT_FALSE(bad);
    EXPECT_NE(bad.message.find("--expect"), std::string::npos) << bad.message;
    std::filesystem::remove_all(f.dir);
}
