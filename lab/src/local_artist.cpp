// The local artist: pick a region, navigate its bank, paint the choice with the soft brush, keep
// the stroke if it helped, repeat (glint/lab/local_artist.h).
#include "glint/lab/local_artist.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "glint/denoise/aids.h"
#include "glint/image/error.h"
#include "glint/image/io.h"
#include "glint/image/metrics.h"
#include "glint/lab/simulated_user.h"

namespace glint::lab {

using denoise::Brush;
using denoise::FilterBank;
using denoise::NavigationTree;

namespace {

// The side of the square region a brush of this size navigates (its diameter, rounded up).
int regionSide(const Brush& brush) {
    return int(std::ceil(brush.size - 1e-9));
}

// The top-left corner of the side × side window of largest Σ map·(1 − tried) over a
// width × height map (scanned row by row: the first of equal sums wins).
std::pair<int, int> busiestWindow(const Image& map, const Image& tried, int side) {
    const int w = map.width(), h = map.height();
    // Summed-area table of map·(1 − tried), (w + 1) × (h + 1).
    std::vector<double> sat(std::size_t(w + 1) * std::size_t(h + 1), 0.0);
    auto at = [&](int x, int y) -> double& { return sat[std::size_t(y) * std::size_t(w + 1) + x]; };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double v = double(map(x, y, 0)) * (1.0 - double(tried(x, y, 0)));
            at(x + 1, y + 1) =
                (std::isfinite(v) ? v : 0.0) + at(x, y + 1) + at(x + 1, y) - at(x, y);
        }
    double best = -1.0;
    std::pair<int, int> corner{0, 0};
    for (int y = 0; y + side <= h; ++y)
        for (int x = 0; x + side <= w; ++x) {
            const double s = at(x + side, y + side) - at(x, y + side) - at(x + side, y) + at(x, y);
            if (s > best + 1e-12) best = s, corner = {x, y};
        }
    return corner;
}

// One dab of the soft brush centred at (cx, cy) paints `source` into `target` (same size):
// target ← target·(1 − w) + source·w, the session's blend (docs/painting.md).
void paintDab(Image& target, const Image& source, double cx, double cy, const Brush& brush) {
    const Rect dab = dabRect(cx, cy, brush, target.width(), target.height());
    for (int y = dab.y0; y < dab.y1; ++y)
        for (int x = dab.x0; x < dab.x1; ++x) {
            const float wt = brushWeight(std::hypot(x + 0.5 - cx, y + 0.5 - cy), brush);
            for (int c = 0; c < 3; ++c)
                target(x, y, c) = target(x, y, c) * (1.0f - wt) + source(x, y, c) * wt;
        }
}

// The members' disagreement in display values (exposure, clamp, sRGB: what the artist sees, so
// that a bright light's noise does not outweigh the rest of the frame).
Image displayVarianceMap(const std::vector<const Image*>& results, float exposure) {
    const float scale = std::exp2(exposure);
    std::vector<Image> display;
    display.reserve(results.size());
    for (const Image* im : results) {
        Image d = *im;
        for (float& v : d.data()) v = srgbEncode(std::clamp(v * scale, 0.0f, 1.0f));
        display.push_back(std::move(d));
    }
    std::vector<const Image*> pointers;
    for (const Image& d : display) pointers.push_back(&d);
    return denoise::filterVarianceMap(pointers);
}

// 1 − SSIM per pixel (clamped at 0): where the composite looks wrong.
Image dissimilarityMap(const Image& composite, const Image& reference, const MetricOptions& mo) {
    Image map = ssimMap(composite, reference, mo);
    for (float& v : map.data()) v = std::max(0.0f, 1.0f - v);
    return map;
}

}  // namespace

ArtistPick parseArtistPick(const std::string& name) {
    if (name == "variance") return ArtistPick::Variance;
    if (name == "error") return ArtistPick::Error;
    throw Error(ErrorKind::InvalidArgument,
                "unknown pick '" + name + "' (expected variance or error)", {}, "--pick");
}

const char* artistPickName(ArtistPick pick) {
    return pick == ArtistPick::Variance ? "variance" : "error";
}

void validate(const LocalArtistOptions& options) {
    if (options.strokes < 1 || options.strokes > 10000)
        throw Error(ErrorKind::InvalidArgument,
                    std::to_string(options.strokes) + " strokes: expected 1 … 10000", {},
                    "--strokes");
    validate(options.brush);
    if (options.brush.size < 11.0)
        throw Error(ErrorKind::InvalidArgument,
                    "brush size " + std::to_string(options.brush.size) +
                        " is below 11 px: the region navigated is the brush's square, and SSIM "
                        "needs 11x11",
                    {}, "--brush-size");
    validate(options.tree);
    if (!std::isfinite(options.exposure))
        throw Error(ErrorKind::InvalidArgument, "the exposure must be finite", {}, "--exposure");
}

LocalArtistResult localArtist(const FilterBank& bank, const Image& start, const Image& reference,
                              const LocalArtistOptions& options) {
    validate(options);
    if (bank.size() == 0) throw Error(ErrorKind::InvalidArgument, "the bank has no members");
    const Rect& region = bank.region();
    const int w = region.width(), h = region.height();
    for (const Image* im : {&start, &reference})
        if (im->width() != w || im->height() != h || im->channels() != 3)
            throw Error(ErrorKind::InvalidArgument,
                        "the start and the reference must be 3-channel images of the bank's "
                        "region (" +
                            std::to_string(w) + "x" + std::to_string(h) + ")");
    const int side = regionSide(options.brush);
    if (side > std::min(w, h))
        throw Error(ErrorKind::InvalidArgument,
                    "brush size " + std::to_string(options.brush.size) + " does not fit in the " +
                        std::to_string(w) + "x" + std::to_string(h) + " region of the bank",
                    {}, "--brush-size");
    MetricOptions mo;
    mo.exposure = options.exposure;

    LocalArtistResult result;
    result.composite = start;
    Image& composite = result.composite;
    double current = ssim(composite, reference, mo).value;
    result.startSsim = current;
    std::vector<const Image*> results;
    for (const Image& im : bank.results()) results.push_back(&im);
    // What draws the artist: the members' disagreement (fixed), or the composite's error
    // (updated after every kept stroke).
    Image priority = options.pick == ArtistPick::Variance
                         ? displayVarianceMap(results, options.exposure)
                         : dissimilarityMap(composite, reference, mo);
    // The squares stroked so far: the next pick counts only the priority outside them.
    Image tried(w, h, 1, 0.0f);
    for (int stroke = 1; stroke <= options.strokes; ++stroke) {
        // Pick the region: the brush's square where the priority, less what was tried, is largest.
        const auto [x0, y0] = busiestWindow(priority, tried, side);
        const Rect local{x0, x0 + side, y0, y0 + side};
        const Rect frameRect{region.x0 + x0, region.x0 + x0 + side, region.y0 + y0,
                             region.y0 + y0 + side};
        // Navigate the region's bank toward the reference there.
        const NavigationTree tree = NavigationTree::fromBank(bank, options.tree, frameRect);
        // The user compares each member as it would look painted there (in context) or alone.
        const Image compositeCrop = composite.crop(local);
        const double half = 0.5 * side;
        std::vector<Image> crops;
        crops.reserve(results.size());
        for (const Image* im : results) {
            crops.push_back(im->crop(local));
            if (options.inContext) {
                Image painted = compositeCrop;
                paintDab(painted, crops.back(), half, half, options.brush);
                crops.back() = std::move(painted);
            }
        }
        std::vector<const Image*> cropPointers;
        for (const Image& im : crops) cropPointers.push_back(&im);
        const std::vector<SimulatedChoice> steps =
            simulateUser(tree, cropPointers, reference.crop(local), options.exposure);
        const int member = steps.back().member;
        // Paint one dab of the soft brush at the square's centre.
        const double cx = x0 + half, cy = y0 + half;
        const Rect dab = dabRect(cx, cy, options.brush, w, h);
        const Image before = composite.crop(dab);
        paintDab(composite, *results[std::size_t(member)], cx, cy, options.brush);
        for (int y = local.y0; y < local.y1; ++y)
            for (int x = local.x0; x < local.x1; ++x) tried(x, y, 0) = 1.0f;
        // Keep it if the whole composite got no worse (or always, when told so).
        const double painted = ssim(composite, reference, mo).value;
        const bool keep = !options.keepOnlyHelping || painted >= current;
        if (keep) {
            current = painted;
            if (options.pick == ArtistPick::Error)
                priority = dissimilarityMap(composite, reference, mo);
        } else {
            for (int y = dab.y0; y < dab.y1; ++y)
                for (int x = dab.x0; x < dab.x1; ++x)
                    for (int c = 0; c < 3; ++c)
                        composite(x, y, c) = before(x - dab.x0, y - dab.y0, c);
        }
        result.strokes.push_back({stroke, region.x0 + cx, region.y0 + cy, frameRect, member,
                                  int(steps.size()), current, painted, keep});
    }
    return result;
}

}  // namespace glint::lab
