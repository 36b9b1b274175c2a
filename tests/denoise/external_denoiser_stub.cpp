// A stand-in for a user's denoiser, run by external_test.cpp through the external filter:
//   external_denoiser_stub MODE exr|pfm COLOR OUTPUT [MARKER]
// Every mode first checks that COLOR holds only finite values (exit 5 otherwise), writes a stray
// file into its working folder (which Glint must remove) and, when MARKER is given, creates it.
//   good     writes COLOR × 0.5 to OUTPUT
//   exit     prints two lines on stderr and exits with code 3
//   abort    dies of SIGABRT
//   size     writes an image one pixel wider than COLOR
//   nan      writes COLOR × 0.5 with one NaN
//   missing  exits 0 without writing OUTPUT
//   sleep    sleeps for a minute (for the timeout and cancel tests)
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <string>

#include "filters/external_files.h"

int main(int argc, char** argv) {
    using glint::denoise::detail::ExchangeFormat;
    if (argc < 5) {
        std::fprintf(stderr, "usage: %s MODE exr|pfm COLOR OUTPUT [MARKER]\n", argv[0]);
        return 64;
    }
    const std::string mode = argv[1];
    const ExchangeFormat format =
        std::string(argv[2]) == "pfm" ? ExchangeFormat::Pfm : ExchangeFormat::Exr;
    std::ofstream("stray.txt") << "left in the working folder\n";
    if (argc > 5) std::ofstream(argv[5]) << "ran\n";
    try {
        glint::Image color = glint::denoise::detail::readExchangeImage(argv[3], format);
        if (color.countNonFinite() != 0) {
            std::fprintf(stderr, "non-finite input\n");
            return 5;
        }
        for (float& v : color.data()) v *= 0.5f;
        if (mode == "good") {
            glint::denoise::detail::writeExchangeImage(color, argv[4], format);
        } else if (mode == "exit") {
            std::fprintf(stderr, "loading the model\nfatal: the model file is damaged\n");
            return 3;
        } else if (mode == "abort") {
            std::abort();
        } else if (mode == "size") {
            glint::denoise::detail::writeExchangeImage(
                glint::Image(color.width() + 1, color.height(), 3, 0.5f), argv[4], format);
        } else if (mode == "nan") {
            color(0, 0, 1) = std::numeric_limits<float>::quiet_NaN();
            glint::denoise::detail::writeExchangeImage(color, argv[4], format);
        } else if (mode == "sleep") {
            ::sleep(60);
        } else if (mode != "missing") {
            std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
            return 64;
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 6;
    }
    return 0;
}
