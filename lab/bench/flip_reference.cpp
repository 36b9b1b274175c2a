// Prints the authors' FLIP means for the pairs of tests/image/flip_pairs.h as the table that
// tests/image/flip_test.cpp holds. Built and run by lab/bench/flip_reference.sh against a
// checkout of https://github.com/NVlabs/flip (BSD-3; not part of Glint, not built by CMake).
#include <cstdio>
#include <string>

#include "FLIP.h"
#include "flip_pairs.h"

int main() {
    struct Setting {
        const char* pair;
        float ppd;  // <= 0: the authors' default
        const char* toneMapper;
    };
    const Setting settings[] = {
        {"ldr-noise", 0, "aces"},      {"ldr-blur", 0, "aces"},      {"ldr-shift", 0, "aces"},
        {"ldr-fireflies", 0, "aces"},  {"hdr-noise", 0, "aces"},     {"hdr-blur", 0, "aces"},
        {"hdr-shift", 0, "aces"},      {"hdr-fireflies", 0, "aces"}, {"ldr-noise", 30, "aces"},
        {"ldr-blur", 30, "aces"},      {"hdr-noise", 30, "aces"},    {"hdr-noise", 0, "hable"},
        {"hdr-fireflies", 0, "hable"}, {"hdr-shift", 0, "reinhard"}};
    const auto pairs = flip_pairs::pairs();
    for (const Setting& s : settings)
        for (const auto& p : pairs) {
            if (p.name != s.pair) continue;
            FLIP::Parameters parameters;
            if (s.ppd > 0) parameters.PPD = s.ppd;
            parameters.tonemapper = s.toneMapper;
            float mean = 0.0f;
            float* map = nullptr;
            FLIP::evaluate(p.reference.data(), p.test.data(), flip_pairs::kWidth,
                           flip_pairs::kHeight, p.hdr, parameters, false, true, mean, &map);
            delete[] map;
            std::printf("    {\"%s\", %.6f, \"%s\", %.9f, %.6f, %.6f, %d},\n", s.pair,
                        parameters.PPD, s.toneMapper, mean, p.hdr ? parameters.startExposure : 0.0f,
                        p.hdr ? parameters.stopExposure : 0.0f,
                        p.hdr ? parameters.numExposures : 1);
        }
}
