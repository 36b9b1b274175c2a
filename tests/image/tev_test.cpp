// tev's IPC protocol: the exact bytes Glint sends, every packet version tev clients send
// (pbrt-v4's UpdateImage, tev's V2 and V3), malformed packets refused naming the byte, the
// images a client builds, and the client against a stand-in tev (tev_test_server.h).
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/image/tev_client.h"
#include "glint/image/tev_images.h"
#include "glint/image/tev_protocol.h"
#include "tev_test_server.h"

namespace glint::tev {
namespace {

using Bytes = std::vector<unsigned char>;

/// Builds a packet by hand, as another client writes it; the length is filled in by bytes().
struct HandPacket {
    Bytes b{0, 0, 0, 0};
    HandPacket& u8(unsigned v) {
        b.push_back((unsigned char)v);
        return *this;
    }
    template <typename T>
    HandPacket& le(T v) {
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, &v, sizeof(T));  // the test machine is little-endian (x86, arm64)
        b.insert(b.end(), raw, raw + sizeof(T));
        return *this;
    }
    HandPacket& str(const std::string& s) {
        b.insert(b.end(), s.begin(), s.end());
        b.push_back(0);
        return *this;
    }
    Bytes bytes() const {
        Bytes out = b;
        const auto n = std::uint32_t(out.size());
        std::memcpy(out.data(), &n, 4);
        return out;
    }
};

/// A 3-pixel-wide, 2-high frame with colour, albedo and depth whose values say where they are.
FrameBuffers tevFrame(int w = 3, int h = 2) {
    FrameBuffers f(w, h);
    f.ensure(Layer::Albedo);
    f.ensure(Layer::Depth);
    f.ensure(Layer::HalfColor);  // never sent
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            for (int c = 0; c < 3; ++c) {
                f.color()(x, y, c) = float(100 * y + 10 * x + c);
                f.layer(Layer::Albedo)(x, y, c) = 0.5f + float(c);
            }
            f.layer(Layer::Depth)(x, y, 0) = float(x + y);
        }
    return f;
}

TEST(TevProtocol, CreateImageIsTheBytesTevReads) {
    const Bytes bytes = encode(CreateImage{"img", true, 640, 480, {"R", "G"}});
    const Bytes expected = HandPacket{}
                               .u8(4)
                               .u8(1)
                               .str("img")
                               .le(std::int32_t(640))
                               .le(std::int32_t(480))
                               .le(std::int32_t(2))
                               .str("R")
                               .str("G")
                               .bytes();
    EXPECT_EQ(bytes, expected);
}

TEST(TevProtocol, UpdateImageIsVersionThreeWithInterleavedOffsetsAndStrides) {
    const UpdateImage u{"img", false, {"R", "albedo.R"}, 4, 5, 2, 1, {1.f, 2.f, 3.f, 4.f}};
    const Bytes bytes = encode(u);
    HandPacket expected;
    expected.u8(6).u8(0).str("img").le(std::int32_t(2)).str("R").str("albedo.R");
    for (int v : {4, 5, 2, 1}) expected.le(std::int32_t(v));
    expected.le(std::int64_t(0)).le(std::int64_t(1)).le(std::int64_t(2)).le(std::int64_t(2));
    for (float v : {1.f, 2.f, 3.f, 4.f}) expected.le(v);
    EXPECT_EQ(bytes, expected.bytes());
    const auto back = std::get<UpdateImage>(decode(bytes));
    EXPECT_EQ(back.channels, u.channels);
    EXPECT_EQ(back.pixels, u.pixels);
    EXPECT_EQ(back.x, 4);
    EXPECT_EQ(back.y, 5);
}

TEST(TevProtocol, EveryPacketRoundTrips) {
    const auto open = std::get<OpenImage>(decode(encode(OpenImage{"/a/b.exr", "albedo", true})));
    EXPECT_EQ(open.path, "/a/b.exr");
    EXPECT_EQ(open.channelSelector, "albedo");
    EXPECT_TRUE(open.grabFocus);
    EXPECT_EQ(std::get<ReloadImage>(decode(encode(ReloadImage{"x", false}))).name, "x");
    EXPECT_EQ(std::get<CloseImage>(decode(encode(CloseImage{"x"}))).name, "x");
    const auto c = std::get<CreateImage>(decode(encode(CreateImage{"n", false, 7, 9, {"Y"}})));
    EXPECT_EQ(c.width, 7);
    EXPECT_EQ(c.height, 9);
    EXPECT_EQ(c.channels, std::vector<std::string>{"Y"});
    EXPECT_THROW(encode(CloseImage{std::string("a\0b", 3)}), Error);
    EXPECT_THROW(encode(UpdateImage{"n", false, {"R"}, 0, 0, 2, 2, {1.f}}), Error);
}

TEST(TevProtocol, PbrtsOneChannelUpdatesAndVersionTwoPlanesAreRead) {
    // pbrt-v4 (src/pbrt/util/display.cpp) sends UpdateImage version 1: one channel a packet.
    HandPacket v1;
    v1.u8(3).u8(0).str("pbrt (42)").str("G");
    for (int v : {1, 0, 2, 1}) v1.le(std::int32_t(v));
    v1.le(5.f).le(6.f);
    const auto u1 = std::get<UpdateImage>(decode(v1.bytes()));
    EXPECT_EQ(u1.name, "pbrt (42)");
    EXPECT_EQ(u1.channels, std::vector<std::string>{"G"});
    EXPECT_EQ(u1.pixels, (std::vector<float>{5.f, 6.f}));
    // Version 2: every channel's plane after the other.
    HandPacket v2;
    v2.u8(5).u8(0).str("i").le(std::int32_t(2)).str("R").str("G");
    for (int v : {0, 0, 2, 1}) v2.le(std::int32_t(v));
    for (float v : {1.f, 2.f, 10.f, 20.f}) v2.le(v);
    EXPECT_EQ(std::get<UpdateImage>(decode(v2.bytes())).pixels,
              (std::vector<float>{1.f, 10.f, 2.f, 20.f}));
    // OpenImage version 1 holds "path:channels".
    const auto o = std::get<OpenImage>(decode(HandPacket{}.u8(0).u8(1).str("a.exr:R").bytes()));
    EXPECT_EQ(o.path, "a.exr");
    EXPECT_EQ(o.channelSelector, "R");
}

/// The message of the Format error `bytes` give, or "" when they decode.
std::string tevDecodeError(const Bytes& bytes) {
    try {
        decode(bytes);
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
        EXPECT_EQ(e.file(), "tev packet");
        return e.what();
    }
    return "";
}

TEST(TevProtocol, MalformedPacketsAreFormatErrorsNamingTheByte) {
    const Bytes good =
        encode(UpdateImage{"img", false, {"R", "G"}, 0, 0, 2, 2, {1, 2, 3, 4, 5, 6, 7, 8}});
    // Every truncation (the length field fixed up to the bytes left) is refused.
    for (std::size_t n = 5; n < good.size(); ++n) {
        Bytes cut(good.begin(), good.begin() + std::ptrdiff_t(n));
        const auto length = std::uint32_t(n);
        std::memcpy(cut.data(), &length, 4);
        EXPECT_NE(tevDecodeError(cut), "") << n << " bytes";
    }
    // A length field that is not the packet's.
    Bytes wrongLength = good;
    wrongLength[0] ^= 1;
    EXPECT_NE(tevDecodeError(wrongLength).find("length field"), std::string::npos);
    // Unknown types.
    for (unsigned type : {9u, 200u, 255u})
        EXPECT_NE(tevDecodeError(HandPacket{}.u8(type).u8(0).str("x").bytes())
                      .find("unknown packet type"),
                  std::string::npos);
    // Huge sizes and channel counts, claimed by a few bytes.
    const auto create = [](std::int32_t w, std::int32_t h, std::int32_t n) {
        return HandPacket{}.u8(4).u8(0).str("x").le(w).le(h).le(n).str("R").bytes();
    };
    EXPECT_NE(tevDecodeError(create(1 << 20, 1 << 20, 1)).find("65536"), std::string::npos);
    EXPECT_NE(tevDecodeError(create(0, 5, 1)), "");
    EXPECT_NE(tevDecodeError(create(-3, 5, 1)), "");
    EXPECT_NE(tevDecodeError(create(4, 4, 1 << 30)).find("channel count"), std::string::npos);
    EXPECT_NE(tevDecodeError(create(4, 4, 0)).find("channel count"), std::string::npos);
    // Offsets and strides that read past the values sent, or backwards.
    const auto v3 = [](std::int64_t offset, std::int64_t stride) {
        HandPacket p;
        p.u8(6).u8(0).str("i").le(std::int32_t(1)).str("R");
        for (int v : {0, 0, 2, 2}) p.le(std::int32_t(v));
        p.le(offset).le(stride);
        for (int i = 0; i < 4; ++i) p.le(1.f);
        return p.bytes();
    };
    EXPECT_EQ(tevDecodeError(v3(0, 1)), "");
    EXPECT_NE(tevDecodeError(v3(1, 1)).find("reads past"), std::string::npos);
    EXPECT_NE(tevDecodeError(v3(0, 2)).find("reads past"), std::string::npos);
    EXPECT_NE(tevDecodeError(v3(-1, 1)), "");
    EXPECT_NE(tevDecodeError(v3(0, -1)), "");
    EXPECT_NE(tevDecodeError(v3(std::int64_t(1) << 62, std::int64_t(1) << 62)), "");
    // A string without its NUL.
    Bytes noNul = HandPacket{}.u8(2).bytes();
    noNul.push_back('a');
    noNul[0] = std::uint8_t(noNul.size());
    EXPECT_NE(tevDecodeError(noNul).find("NUL"), std::string::npos);
}

TEST(TevProtocol, AStreamIsSplitIntoPacketsWhateverTheReadsAndABrokenLengthStopsIt) {
    const Bytes a = encode(CloseImage{"a"}), b = encode(CreateImage{"b", false, 1, 1, {"R"}});
    Bytes both = a;
    both.insert(both.end(), b.begin(), b.end());
    PacketStream stream;
    std::vector<Bytes> got;
    for (unsigned char byte : both) {  // one byte a read
        stream.append({&byte, 1});
        while (auto p = stream.next()) got.push_back(*p);
    }
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0], a);
    EXPECT_EQ(got[1], b);
    EXPECT_EQ(stream.buffered(), 0u);
    for (std::uint32_t length : {0u, 4u, 0xFFFFFFFFu, kMaxPacketBytes + 1}) {
        PacketStream broken;
        unsigned char raw[8] = {};
        std::memcpy(raw, &length, 4);
        broken.append(raw);
        EXPECT_THROW(broken.next(), Error) << length;
    }
}

TEST(TevProtocol, RandomlyDamagedPacketsAreErrorsOrPacketsNeverACrash) {
    // A little fuzzing (fixed seed): bytes of valid packets overwritten at random, then decoded
    // and applied to an image; anything but a glint::Error escaping fails.
    const std::vector<Bytes> valid = {
        encode(CreateImage{"i", false, 8, 4, {"R", "G", "B", "albedo.R"}}),
        encode(UpdateImage{"i", false, {"R", "G"}, 2, 1, 3, 2, std::vector<float>(12, 0.5f)}),
        encode(CloseImage{"i"}), encode(OpenImage{"p.exr", "R", true})};
    std::mt19937 rng(50);
    int decoded = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        Bytes b = valid[std::size_t(trial) % valid.size()];
        const int flips = 1 + int(rng() % 4);
        for (int f = 0; f < flips; ++f) b[4 + rng() % (b.size() - 4)] = (unsigned char)rng();
        if (rng() % 8 == 0) b.resize(5 + rng() % (b.size() - 4));
        ReceivedImages images;
        images.apply(CreateImage{"i", false, 8, 4, {"R", "G", "B", "albedo.R"}});
        try {
            const Packet p = decode(b);
            ++decoded;
            images.apply(p, 64 << 20);
        } catch (const Error&) {
        }
    }
    EXPECT_GT(decoded, 0);  // some damage leaves a valid packet (a changed value)
}

TEST(TevImages, UpdatesFillTilesAndTheFrameHasTheLayersTheNamesSay) {
    ReceivedImages images;
    const FrameBuffers sent = tevFrame(5, 4);
    EXPECT_EQ(images.apply(createPacket("r", sent)).kind, Change::Created);
    forEachTile(sent, "r", 2, [&](const UpdateImage& u) {
        EXPECT_EQ(images.apply(u).kind, Change::Updated);
        return true;
    });
    const FrameBuffers got = images.frame("r");
    ASSERT_EQ(got.width(), 5);
    EXPECT_EQ(got.metadata().source, "glint");
    for (Layer l : {Layer::Color, Layer::Albedo, Layer::Depth}) {
        ASSERT_TRUE(got.has(l)) << layerDisplayName(l);
        EXPECT_EQ(std::vector<float>(got.layer(l).data().begin(), got.layer(l).data().end()),
                  std::vector<float>(sent.layer(l).data().begin(), sent.layer(l).data().end()));
    }
    EXPECT_FALSE(got.has(Layer::HalfColor));
    EXPECT_EQ(images.apply(CloseImage{"r"}).kind, Change::Closed);
    EXPECT_TRUE(images.complete("r"));
    EXPECT_EQ(images.apply(OpenImage{"f.exr", "", false}).kind, Change::None);
}

TEST(TevImages, PacketsThatDoNotFitTheImageAreRefusedAndChangeNothing) {
    ReceivedImages images;
    images.apply(CreateImage{"i", false, 4, 4, {"R", "G", "B"}});
    const auto refused = [&](const Packet& p, const std::string& says) {
        try {
            images.apply(p);
            ADD_FAILURE() << packetName(p) << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
        }
    };
    refused(UpdateImage{"i", false, {"R"}, 3, 3, 2, 1, {1, 1}}, "outside the 4x4 image");
    refused(UpdateImage{"i", false, {"R"}, -1, 0, 1, 1, {1}}, "outside");
    refused(UpdateImage{"i", false, {"R"}, 2147483647, 0, 1, 1, {1}}, "outside");
    refused(UpdateImage{"i", false, {"albedo.R"}, 0, 0, 1, 1, {1}}, "not created with");
    refused(UpdateImage{"i", false, {"R", "R"}, 0, 0, 1, 1, {1, 2}}, "twice");
    refused(UpdateImage{"none", false, {"R"}, 0, 0, 1, 1, {1}}, "no image of this name");
    refused(CloseImage{"none"}, "no image of this name");
    refused(CreateImage{"j", false, 4, 4, {"R", "R"}}, "twice");
    refused(CreateImage{"big", false, 65536, 4096, std::vector<std::string>(1024, "x")}, "");
    // A memory limit: a new image needing more is refused before anything is allocated.
    try {
        images.apply(CreateImage{"k", false, 1024, 1024, {"R", "G", "B"}}, 1 << 20);
        ADD_FAILURE() << "a 12 MiB image fit in 1 MiB";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::OutOfMemory);
    }
    EXPECT_FALSE(images.has("k"));
    const FrameBuffers f = images.frame("i");
    for (float v : f.color().data()) EXPECT_EQ(v, 0.0f);
}

TEST(TevImages, ForeignChannelNamesAreReadAsTheirLayersOrTheFirstChannelsAsColour) {
    ReceivedImages images;
    // pbrt-v4's per-sample variance is left out (its sample count is unknown).
    images.apply(CreateImage{"p",
                             false,
                             1,
                             1,
                             {"R", "G", "B", "Albedo.R", "Albedo.G", "Albedo.B", "Variance.R",
                              "Variance.G", "Variance.B"}});
    images.apply(UpdateImage{"p", false, {"Albedo.G"}, 0, 0, 1, 1, {0.25f}});
    const FrameBuffers p = images.frame("p");
    EXPECT_EQ(p.metadata().source, "pbrt");
    EXPECT_EQ(p.layer(Layer::Albedo)(0, 0, 1), 0.25f);
    EXPECT_FALSE(p.has(Layer::Variance));
    // One channel "Y": grey.
    images.apply(CreateImage{"y", false, 1, 1, {"Y"}});
    images.apply(UpdateImage{"y", false, {"Y"}, 0, 0, 1, 1, {3.0f}});
    const FrameBuffers y = images.frame("y");
    for (int c = 0; c < 3; ++c) EXPECT_EQ(y.color()(0, 0, c), 3.0f);
}

TEST(TevClient, AddressesAreHostColonPort) {
    EXPECT_EQ(parseAddress("127.0.0.1:14158", "--display").port, 14158);
    EXPECT_EQ(parseAddress("[::1]:9", "--display").host, "::1");
    EXPECT_EQ(parseAddress("viewer.local:1", "--display").host, "viewer.local");
    for (const char* bad : {"", "14158", ":14158", "host:", "host:0", "host:65536", "host:1x"}) {
        try {
            parseAddress(bad, "--display");
            ADD_FAILURE() << bad;
        } catch (const Error& e) {
            EXPECT_EQ(e.where(), "--display") << bad;
        }
    }
}

TEST(TevClient, ADisplaySendsCreateThenEveryTileOfEachFrameThenClose) {
    glint::testing::TevTestServer server;
    const FrameBuffers frame = tevFrame(5, 3);
    std::vector<std::string> warnings;
    {
        Display display({parseAddress(server.address(), "test"), "render.exr", true, 2,
                         [&](const std::string& w) { warnings.push_back(w); }});
        display.show(std::make_shared<FrameBuffers>(frame));
        display.finish();
        EXPECT_FALSE(display.failed());
    }
    const auto& packets = server.packets();
    EXPECT_EQ(server.error(), "");
    EXPECT_TRUE(warnings.empty());
    // Create, 3 × 2 tiles of at most 2×2, close.
    ASSERT_EQ(packets.size(), 8u);
    const auto& create = std::get<CreateImage>(packets[0]);
    EXPECT_EQ(create.name, "render.exr");
    EXPECT_EQ(create.width, 5);
    EXPECT_EQ(create.height, 3);
    const std::vector<std::string> channels{"R",        "G",        "B",      "albedo.R",
                                            "albedo.G", "albedo.B", "depth.Z"};
    EXPECT_EQ(create.channels, channels);
    ReceivedImages images;
    images.apply(create);
    std::vector<int> covered(15, 0);
    for (std::size_t i = 1; i + 1 < packets.size(); ++i) {
        const auto& u = std::get<UpdateImage>(packets[i]);
        EXPECT_EQ(u.channels, channels);
        EXPECT_LE(u.width, 2);
        EXPECT_LE(u.height, 2);
        EXPECT_EQ(server.rawPackets()[i][4], std::uint8_t(PacketType::UpdateImageV3));
        for (int y = u.y; y < u.y + u.height; ++y)
            for (int x = u.x; x < u.x + u.width; ++x) ++covered[std::size_t(y * 5 + x)];
        images.apply(u);
    }
    for (int c : covered) EXPECT_EQ(c, 1);  // every pixel in exactly one tile
    EXPECT_EQ(std::get<CloseImage>(packets.back()).name, "render.exr");
    const FrameBuffers got = images.frame("render.exr");
    EXPECT_EQ(got.color()(4, 2, 1), frame.color()(4, 2, 1));
    EXPECT_EQ(got.layer(Layer::Depth)(3, 1, 0), frame.layer(Layer::Depth)(3, 1, 0));
}

TEST(TevClient, ARefusedConnectionWarnsOnceAndTheCallerGoesOn) {
    std::vector<std::string> warnings;
    Display display(
        {{"127.0.0.1", glint::testing::unusedPort()}, "x", true, 2, [&](const std::string& w) {
             warnings.push_back(w);
         }});
    for (int pass = 0; pass < 3; ++pass) display.show(std::make_shared<FrameBuffers>(tevFrame()));
    display.finish();
    EXPECT_TRUE(display.failed());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("refused"), std::string::npos) << warnings[0];
    EXPECT_NE(warnings[0].find("going on without it"), std::string::npos) << warnings[0];
}

TEST(TevClient, AConnectionLostMidwayWarnsOnceAndStopsSending) {
    glint::testing::TevTestServer server(1);  // tev quits after the CreateImage
    std::vector<std::string> warnings;
    Display display({parseAddress(server.address(), "test"), "x", true, 1,
                     [&](const std::string& w) { warnings.push_back(w); }});
    display.show(std::make_shared<FrameBuffers>(tevFrame(64, 64)));
    EXPECT_EQ(server.packets().size(), 1u);
    // Frames shown after the loss: the sends fail (on these at the latest), warned once.
    for (int pass = 0; pass < 3; ++pass)
        display.show(std::make_shared<FrameBuffers>(tevFrame(64, 64)));
    display.finish();
    EXPECT_TRUE(display.failed());
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("lost"), std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace glint::tev
