// Helpers for renderer tests: temporary scene folders, tessellated meshes, chi-square test.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "glint/image/error.h"
#include "glint/image/frame_buffers.h"
#include "glint/image/mc_compare.h"
#include "glint/render/settings.h"

namespace glint::render::test {

/// True when `layer` of a and b holds the same bits.
inline bool sameLayer(const FrameBuffers& a, const FrameBuffers& b, Layer layer) {
    const auto da = a.layer(layer).data(), db = b.layer(layer).data();
    return da.size() == db.size() && std::memcmp(da.data(), db.data(), da.size_bytes()) == 0;
}

/// Expects a and b to have the same layers, each bit-identical.
inline void expectSameFrames(const FrameBuffers& a, const FrameBuffers& b) {
    for (int l = 0; l < kLayerCount; ++l) {
        const Layer layer = Layer(l);
        ASSERT_EQ(a.has(layer), b.has(layer)) << layerInfo(layer).name;
        if (a.has(layer)) {
            EXPECT_TRUE(sameLayer(a, b, layer)) << layerInfo(layer).name;
        }
    }
}

/// The message of the glint::Error `f` throws, or "" when it throws none.
template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// A fresh directory under the system temp folder, removed on destruction.
class TempDir {
  public:
    explicit TempDir(const std::string& name) {
        static int counter = 0;
        m_path = std::filesystem::temp_directory_path() /
                 ("glint_render_" + name + "_" + std::to_string(::getpid()) + "_" +
                  std::to_string(counter++));
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    const std::filesystem::path& path() const { return m_path; }
    /// Writes a text file inside the directory and returns its path.
    std::filesystem::path write(const std::string& name, const std::string& text) const {
        const auto p = m_path / name;
        std::ofstream(p) << text;
        return p;
    }

  private:
    std::filesystem::path m_path;
};

/// OBJ text of an 18 × 18 square (two triangles, facing +z) in the plane z = `z`: the floor
/// of the alpha and cluster tests.
inline std::string floorObj(int z) {
    const std::string h = " " + std::to_string(z) + "\n";
    return "v -9 -9" + h + "v 9 -9" + h + "v 9 9" + h + "v -9 9" + h + "f 1 2 3\nf 1 3 4\n";
}

/// OBJ text of a flat-shaded UV sphere (no vertex normals) of radius r at the origin.
inline std::string sphereObj(float r, int stacks = 16, int slices = 32) {
    std::string s;
    const double pi = 3.14159265358979323846;
    s += "v 0 " + std::to_string(r) + " 0\n";
    for (int i = 1; i < stacks; ++i) {
        const double theta = pi * i / stacks;
        for (int j = 0; j < slices; ++j) {
            const double phi = 2 * pi * j / slices;
            s += "v " + std::to_string(r * std::sin(theta) * std::cos(phi)) + " " +
                 std::to_string(r * std::cos(theta)) + " " +
                 std::to_string(r * std::sin(theta) * std::sin(phi)) + "\n";
        }
    }
    s += "v 0 " + std::to_string(-r) + " 0\n";
    const int bottom = 2 + (stacks - 1) * slices;
    auto ring = [&](int i, int j) { return 2 + (i - 1) * slices + (j % slices); };
    for (int j = 0; j < slices; ++j)
        s += "f 1 " + std::to_string(ring(1, j + 1)) + " " + std::to_string(ring(1, j)) + "\n";
    for (int i = 1; i < stacks - 1; ++i)
        for (int j = 0; j < slices; ++j)
            s += "f " + std::to_string(ring(i, j)) + " " + std::to_string(ring(i, j + 1)) + " " +
                 std::to_string(ring(i + 1, j + 1)) + " " + std::to_string(ring(i + 1, j)) + "\n";
    for (int j = 0; j < slices; ++j)
        s += "f " + std::to_string(bottom) + " " + std::to_string(ring(stacks - 1, j)) + " " +
             std::to_string(ring(stacks - 1, j + 1)) + "\n";
    return s;
}

/// OBJ text of the unit quad [-1,1]² in the xz-plane (normal +y) with texture coordinates.
inline std::string quadObj() {
    return "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\n"
           "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
           "f 1/1 4/4 3/3 2/2\n";
}

/// Writes the adaptive-bias tests' scene into `dir` and returns its scene.json: a diffuse ball of
/// albedo (ballRed, 0.3, 0.2) on a floor under a white sky, 32 × 24 (the mc windows of 8 and 16
/// pixels fit): noisy soft shadows and interreflection on the objects, a noiseless sky on top.
inline std::filesystem::path writeBallScene(const TempDir& dir, double ballRed) {
    dir.write("quad.obj", quadObj());
    dir.write("sphere.obj", sphereObj(1.0f));
    return dir.write("scene.json", R"({
      "camera": {"position": [0, 1.2, 3], "lookAt": [0, 0.5, 0], "fovY": 40},
      "film": {"width": 32, "height": 24},
      "materials": {"floor": {"type": "diffuse", "albedo": [0.6, 0.6, 0.6]},
                    "ball": {"type": "diffuse", "albedo": [)" +
                                       std::to_string(ballRed) + R"(, 0.3, 0.2]}},
      "shapes": [{"obj": "quad.obj", "material": "floor", "transform": {"scale": 3}},
                 {"obj": "sphere.obj", "material": "ball",
                  "transform": {"translate": [0, 0.5, 0], "scale": 0.5}}],
      "environment": {"color": [1, 1, 1]},
      "render": {"spp": 8, "maxDepth": 3}
    })");
}

/// A Monte Carlo comparison's result in words, for a test's message.
inline std::string describe(const McCompareResult& r) {
    return "statistic " + std::to_string(r.statistic) + " (threshold " +
           std::to_string(r.threshold) + ", " + std::to_string(r.windows) +
           " windows), worst window x " + std::to_string(r.worstWindow.x0) + ".." +
           std::to_string(r.worstWindow.x1) + ", y " + std::to_string(r.worstWindow.y0) + ".." +
           std::to_string(r.worstWindow.y1) + " differs by " +
           std::to_string(100.0 * r.relativeBias) + " %";
}

/// Regularised upper incomplete gamma Q(a, x) (series / continued fraction, Numerical Recipes
/// sec. 6.2 formulas).
inline double gammaQ(double a, double x) {
    if (x <= 0.0) return 1.0;
    const double lnPrefix = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        double sum = 1.0 / a, term = sum;
        for (int n = 1; n < 10000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return 1.0 - sum * std::exp(lnPrefix);
    }
    // Modified Lentz continued fraction.
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 10000; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < 1e-15) break;
    }
    return std::exp(lnPrefix) * h;
}

/// Pearson chi-square goodness of fit; cells with expected count < minExpected are pooled.
struct Chi2 {
    double statistic = 0.0;
    int dof = 0;
    double pValue = 1.0;
};
inline Chi2 chi2Test(const std::vector<double>& observed, const std::vector<double>& expected,
                     double minExpected = 5.0) {
    Chi2 r;
    double pooledObs = 0.0, pooledExp = 0.0;
    int cells = 0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        if (expected[i] < minExpected) {
            pooledObs += observed[i];
            pooledExp += expected[i];
            continue;
        }
        const double d = observed[i] - expected[i];
        r.statistic += d * d / expected[i];
        ++cells;
    }
    if (pooledExp > 0.0 || pooledObs > 0.0) {
        // A pooled cell with (near) zero expectation but observations is a certain failure.
        const double e = std::max(pooledExp, 1e-12);
        const double d = pooledObs - pooledExp;
        r.statistic += d * d / e;
        ++cells;
    }
    r.dof = std::max(cells - 1, 1);
    r.pValue = gammaQ(0.5 * r.dof, 0.5 * r.statistic);
    return r;
}

/// Šidák-corrected per-test significance for `tests` tests at family-wise level alpha.
inline double sidak(double alpha, int tests) {
    return 1.0 - std::pow(1.0 - alpha, 1.0 / tests);
}

/// The ways of combining light and BSDF sampling that the unbiasedness tests compare: each
/// estimates the same image.
struct MisMode {
    const char* name;
    MisHeuristic mis;
    Strategy strategy;
};
inline constexpr MisMode kMisModes[] = {{"power", MisHeuristic::Power, Strategy::Bsdf},
                                        {"balance", MisHeuristic::Balance, Strategy::Bsdf},
                                        {"light", MisHeuristic::None, Strategy::Light},
                                        {"bsdf", MisHeuristic::None, Strategy::Bsdf}};

/// The mean of channel 0 of `image` over columns [x0, x1) (x1 < 0: to the right edge).
inline double columnsMean(const Image& image, int x0 = 0, int x1 = -1) {
    if (x1 < 0) x1 = image.width();
    double sum = 0.0;
    for (int y = 0; y < image.height(); ++y)
        for (int x = x0; x < x1; ++x) sum += image(x, y, 0);
    return sum / (double(x1 - x0) * image.height());
}

/// The image mean of channel 0 and its standard error, from the variance layer (the pixels'
/// variances of the mean over their count: pixels independent).
struct MeanEstimate {
    double mean, sigma;
};
inline MeanEstimate meanAndError(const FrameBuffers& frame) {
    const Image& var = frame.layer(Layer::Variance);
    return {columnsMean(frame.color()), std::sqrt(columnsMean(var) / double(var.pixelCount()))};
}

}  // namespace glint::render::test
