// glint-render --display: the packets a stand-in tev receives (tev_test_server.h) from the
// built binary, and a tev that is not there, goes away or is misnamed.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "glint/image/io.h"
#include "glint/image/tev_images.h"
#include "scene_cli_fixture.h"
#include "tev_test_server.h"

namespace glint::render {
namespace {

using glint::testing::RunResult;

int countLines(const std::string& text, const std::string& with) {
    int n = 0;
    for (std::size_t at = text.find(with); at != std::string::npos; at = text.find(with, at + 1))
        ++n;
    return n;
}

class DisplayCli : public glint::testing::SceneCliFixture {
  protected:
    DisplayCli() : SceneCliFixture("glint-render", {150, 20, 4}) {}
};

TEST_F(DisplayCli, TevReceivesTheImageCreatedWithItsLayersThenEachPassAsTiles) {
    glint::testing::TevTestServer tev;
    const RunResult r =
        run(path("scene.json") + " --out " + path("a.exr") + " --display " + tev.address());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const auto& packets = tev.packets();
    EXPECT_EQ(tev.error(), "");
    ASSERT_GE(packets.size(), 3u);
    const auto& create = std::get<tev::CreateImage>(packets[0]);
    EXPECT_EQ(create.name, "a.exr");
    EXPECT_EQ(create.width, 150);
    EXPECT_EQ(create.height, 20);
    for (const char* c :
         {"R", "G", "B", "variance.R", "albedo.G", "normal.Z", "depth.Z", "sampleCount.Y"})
        EXPECT_NE(std::find(create.channels.begin(), create.channels.end(), c),
                  create.channels.end())
            << c;
    // Every later packet is a tile of at most 128² of every channel inside the image; the last
    // ones are the frame written.
    tev::ReceivedImages images;
    images.apply(create);
    for (std::size_t i = 1; i < packets.size(); ++i) {
        const auto& u = std::get<tev::UpdateImage>(packets[i]);
        EXPECT_EQ(u.channels, create.channels);
        EXPECT_LE(u.width, 128);
        EXPECT_LE(u.height, 128);
        EXPECT_EQ(tev.rawPackets()[i][4], std::uint8_t(tev::PacketType::UpdateImageV3));
        images.apply(u);
    }
    const FrameBuffers shown = images.frame("a.exr"), written = readExr(path("a.exr"));
    for (Layer l : {Layer::Color, Layer::Variance, Layer::Albedo, Layer::SampleCount}) {
        const auto a = shown.layer(l).data(), b = written.layer(l).data();
        EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << layerDisplayName(l);
    }
}

TEST_F(DisplayCli, NoTevThereIsOneWarningAndTheRenderIsWritten) {
    const RunResult r = run(path("scene.json") + " --out " + path("a.exr") +
                            " --display 127.0.0.1:" + std::to_string(glint::testing::unusedPort()));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(countLines(r.err, "warning: tev at 127.0.0.1:"), 1) << r.err;
    EXPECT_NE(r.err.find("refused"), std::string::npos) << r.err;
    EXPECT_EQ(readExr(path("a.exr")).width(), 150);
}

TEST_F(DisplayCli, ATevThatQuitsMidRenderIsAtMostOneWarningAndTheRenderIsWritten) {
    glint::testing::TevTestServer tev(1);  // quits after the CreateImage
    const RunResult r =
        run(path("scene.json") + " --out " + path("a.exr") + " --display " + tev.address());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(tev.packets().size(), 1u);
    EXPECT_LE(countLines(r.err, "warning: tev at"), 1) << r.err;
    EXPECT_EQ(readExr(path("a.exr")).width(), 150);
}

TEST_F(DisplayCli, AMalformedAddressExitsTwoNamingTheFlagAndWritesNothing) {
    for (const char* bad : {"14158", "localhost:", "localhost:99999", ":1"}) {
        const RunResult r =
            run(path("scene.json") + " --out " + path("a.exr") + " --display " + bad);
        EXPECT_EQ(r.exitCode, 2) << bad;
        EXPECT_NE(r.err.find("--display"), std::string::npos) << r.err;
        EXPECT_EQ(countLines(r.err, "\n"), 1) << r.err;
        EXPECT_FALSE(std::filesystem::exists(path("a.exr")));
    }
}

}  // namespace
}  // namespace glint::render
