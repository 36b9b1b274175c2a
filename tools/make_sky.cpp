// glint-make-sky: writes a procedural HDR sky (gradient sky, soft glow, sun disc) as a lat-long
// half-float EXR in the environment convention of docs/scene-format.md:
//   direction (x, y, z), +y up:  u = 0.5 + atan2(x, -z) / (2 pi),  v = acos(y) / pi,
//   u = 0.5 looks down -z, u = 0.75 towards +x; row 0 (v = 0) is the zenith.
// Each pixel is the average of sub-samples over its (u, v) cell, so the small sun disc is
// antialiased and its power is right even when it covers only a few pixels.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "asset_io.h"
#include "glint/image/error.h"

namespace {

using Rgb = std::array<double, 3>;

/// Parameters of the sky model; angles in degrees.
struct SkyParams {
    int width = 256;
    int height = 128;
    double sunElevation = 35.0;  ///< degrees above the horizon
    double sunAzimuth = 60.0;    ///< degrees from -z towards +x (same as u = 0.5 + az / 360)
    double sunRadius = 5.0;      ///< angular radius of the disc, degrees
    double sunIrradiance = 3.0;  ///< irradiance of the disc on a surface facing it
    int subsamples = 8;          ///< sub-samples per pixel per axis
};

/// Linear interpolation of colours.
Rgb mix(const Rgb& a, const Rgb& b, double t) {
    return {a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t};
}

/// Unit direction of lat-long coordinates (u, v): the inverse of the mapping in the file header.
std::array<double, 3> direction(double u, double v) {
    const double phi = 2.0 * std::numbers::pi * (u - 0.5);
    const double theta = std::numbers::pi * v;
    return {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
}

/// Radiance of the sky model in direction `d`.
Rgb radiance(const std::array<double, 3>& d, const std::array<double, 3>& sun, double cosSunRadius,
             double sunRadiance) {
    const Rgb zenith{0.10, 0.22, 0.60};
    const Rgb horizon{0.70, 0.80, 0.95};
    const Rgb ground{0.18, 0.16, 0.14};
    const Rgb sunColor{1.0, 0.93, 0.82};
    Rgb sky;
    if (d[1] >= 0.0) {
        // Sky: horizon colour fading to zenith colour with elevation.
        sky = mix(horizon, zenith, std::pow(d[1], 0.45));
    } else {
        // Ground below the horizon, blended over a few degrees to avoid a hard seam.
        sky = mix(horizon, ground, std::min(1.0, -d[1] * 12.0));
    }
    const double cosAngle = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
    // Forward-scattering glow around the sun (an empirical exponential lobe).
    const double glow = 0.6 * std::exp(-(1.0 - cosAngle) * 25.0);
    for (int c = 0; c < 3; ++c) sky[c] += glow * sunColor[c];
    if (cosAngle >= cosSunRadius) {
        for (int c = 0; c < 3; ++c) sky[c] += sunRadiance * sunColor[c];
    }
    return sky;
}

/// Renders the lat-long sky, row 0 at the zenith.
std::vector<float> makeSky(const SkyParams& p) {
    const double deg = std::numbers::pi / 180.0;
    const double el = p.sunElevation * deg;
    const double az = p.sunAzimuth * deg;
    const std::array<double, 3> sun{std::cos(el) * std::sin(az), std::sin(el),
                                    -std::cos(el) * std::cos(az)};
    const double cosSunRadius = std::cos(p.sunRadius * deg);
    // Uniform disc of solid angle 2 pi (1 - cos r) giving irradiance E at normal incidence:
    // L = E / omega (small-disc approximation, error < 0.1 % for r < 5 degrees).
    const double omega = 2.0 * std::numbers::pi * (1.0 - cosSunRadius);
    const double sunRadiance = p.sunIrradiance / omega;
    std::vector<float> rgb(std::size_t(p.width) * p.height * 3);
    const int n = p.subsamples;
    for (int y = 0; y < p.height; ++y) {
        for (int x = 0; x < p.width; ++x) {
            Rgb sum{0, 0, 0};
            double weight = 0.0;
            for (int j = 0; j < n; ++j) {
                for (int i = 0; i < n; ++i) {
                    const double u = (x + (i + 0.5) / n) / p.width;
                    const double v = (y + (j + 0.5) / n) / p.height;
                    // Weight sub-samples by sin(theta) so the pixel holds the mean radiance
                    // over its solid angle.
                    const double w = std::sin(std::numbers::pi * v);
                    const Rgb l = radiance(direction(u, v), sun, cosSunRadius, sunRadiance);
                    for (int c = 0; c < 3; ++c) sum[c] += w * l[c];
                    weight += w;
                }
            }
            for (int c = 0; c < 3; ++c) {
                rgb[(std::size_t(y) * p.width + x) * 3 + c] = float(sum[c] / weight);
            }
        }
    }
    return rgb;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"Writes a procedural HDR sky as a lat-long half-float EXR"};
    SkyParams p;
    std::string out;
    app.add_option("--width", p.width, "pixels")->check(CLI::Range(8, 8192))->capture_default_str();
    app.add_option("--height", p.height, "pixels")
        ->check(CLI::Range(4, 4096))
        ->capture_default_str();
    app.add_option("--sun-elevation", p.sunElevation, "degrees above the horizon")
        ->check(CLI::Range(-90.0, 90.0))
        ->capture_default_str();
    app.add_option("--sun-azimuth", p.sunAzimuth, "degrees from -z towards +x")
        ->capture_default_str();
    app.add_option("--sun-radius", p.sunRadius, "angular radius of the disc, degrees")
        ->check(CLI::Range(0.05, 10.0))
        ->capture_default_str();
    app.add_option("--sun-irradiance", p.sunIrradiance,
                   "irradiance of the disc at normal incidence")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    app.add_option("--subsamples", p.subsamples, "sub-samples per pixel per axis")
        ->check(CLI::Range(1, 64))
        ->capture_default_str();
    app.add_option("--out", out, "output EXR")->required();
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    try {
        glint::tools::writeHalfExr(makeSky(p), p.width, p.height, out);
    } catch (const glint::Error& e) {
        std::cerr << "glint-make-sky: " << e.what() << "\n";
        return 1;
    }
    return 0;
}
