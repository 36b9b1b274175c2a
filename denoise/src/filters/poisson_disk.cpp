// Window sampling patterns for bilateral-mc (Banterle et al. 2012 use Poisson-disk patterns
// generated with Bridson's algorithm; the other kinds are for comparison).
#include "filters/poisson_disk.h"

#include <algorithm>
#include <cmath>

#include "glint/image/error.h"

namespace glint::denoise::detail {

std::vector<Offset> bridsonPoissonDisk(int radius, double minDistance, SplitMix64& rng,
                                       int attempts) {
    GLINT_CHECK(radius >= 0 && minDistance > 0.0 && attempts > 0);
    const int n = 2 * radius + 1;
    const double min2 = minDistance * minDistance;
    const int reach = int(std::ceil(2.0 * minDistance));
    // On the lattice Bridson's background grid becomes a "blocked" map: inserting a point blocks
    // every lattice point closer than minDistance, so testing a candidate is one lookup.
    std::vector<Offset> disk, annulus;
    for (int j = -reach; j <= reach; ++j)
        for (int i = -reach; i <= reach; ++i) {
            const double r2 = double(i) * i + double(j) * j;
            if (r2 < min2) disk.push_back({i, j});
            // Bridson 2007: candidates lie in the annulus [r, 2r] around an active point.
            else if (r2 <= 4.0 * min2)
                annulus.push_back({i, j});
        }
    if (annulus.empty())  // minDistance < 0.5: every lattice neighbour is far enough
        annulus = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    std::vector<unsigned char> blocked(std::size_t(n) * std::size_t(n), 0);
    auto at = [&](Offset p) -> unsigned char& {
        return blocked[std::size_t(p.dy + radius) * std::size_t(n) + std::size_t(p.dx + radius)];
    };
    std::vector<Offset> points;
    std::vector<Offset> active;
    auto insert = [&](Offset p) {
        for (const Offset& o : disk) {
            const Offset q{p.dx + o.dx, p.dy + o.dy};
            if (std::abs(q.dx) <= radius && std::abs(q.dy) <= radius) at(q) = 1;
        }
        points.push_back(p);
        active.push_back(p);
    };
    // Step 1: the initial sample is the window centre.
    insert({0, 0});
    // Step 2: while the active list is not empty, try `attempts` candidates around a random
    // active point; keep the first that is far enough from all points, else retire the point.
    while (!active.empty()) {
        const std::size_t slot = rng.below(active.size());
        const Offset base = active[slot];
        bool found = false;
        for (int a = 0; a < attempts && !found; ++a) {
            const Offset& o = annulus[rng.below(annulus.size())];
            const Offset c{base.dx + o.dx, base.dy + o.dy};
            if (std::abs(c.dx) > radius || std::abs(c.dy) > radius || at(c)) continue;
            insert(c);
            found = true;
        }
        if (!found) {
            active[slot] = active.back();
            active.pop_back();
        }
    }
    return points;
}

namespace {

bool isCentre(const Offset& o) {
    return o.dx == 0 && o.dy == 0;
}

// Removes random points other than the centre until `count` remain.
void trimTo(std::vector<Offset>& points, std::size_t count, SplitMix64& rng) {
    while (points.size() > count) {
        const std::size_t i = rng.below(points.size());
        if (isCentre(points[i])) continue;
        points[i] = points.back();
        points.pop_back();
    }
}

// Adds the centre if absent (replacing a random point when the pattern is full).
void ensureCentre(std::vector<Offset>& points, std::size_t count, SplitMix64& rng) {
    if (std::any_of(points.begin(), points.end(), isCentre)) return;
    if (points.size() >= count && !points.empty())
        points[rng.below(points.size())] = {0, 0};
    else
        points.push_back({0, 0});
}

// Drops repeated offsets (rounding can map two continuous points to one pixel).
void unique(std::vector<Offset>& points) {
    std::sort(points.begin(), points.end(), [](const Offset& a, const Offset& b) {
        return a.dy != b.dy ? a.dy < b.dy : a.dx < b.dx;
    });
    points.erase(
        std::unique(points.begin(), points.end(),
                    [](const Offset& a, const Offset& b) { return a.dx == b.dx && a.dy == b.dy; }),
        points.end());
}

}  // namespace

BilateralPattern makeWindowPattern(PatternKind kind, int radius, int count, std::uint64_t seed) {
    GLINT_CHECK(radius >= 0 && count >= 1);
    const int n = 2 * radius + 1;
    const std::size_t windowSize = std::size_t(n) * std::size_t(n);
    BilateralPattern pattern;
    std::vector<Offset>& pts = pattern.offsets;
    const auto target = std::size_t(count);
    if (target >= windowSize) {
        for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx) pts.push_back({dx, dy});
        return pattern;
    }
    SplitMix64 rng(seed * 0xD1B54A32D192ED03ull + std::uint64_t(kind) + 1);
    switch (kind) {
        case PatternKind::Poisson: {
            // A maximal Poisson-disk set holds about 0.6-0.7 A / d^2 points (Bridson's method
            // slightly less than maximal); aim above `count`, shrink d if short, then trim.
            double d = std::sqrt(0.62 * double(windowSize) / double(count));
            for (int attempt = 0; attempt < 12; ++attempt, d *= 0.85) {
                pts = bridsonPoissonDisk(radius, std::max(d, 1e-3), rng);
                if (pts.size() >= target) break;
            }
            trimTo(pts, target, rng);
            break;
        }
        case PatternKind::Regular: {
            const int g = std::max(1, int(std::lround(std::sqrt(double(count)))));
            const double step = double(n) / g;
            for (int j = 0; j < g; ++j)
                for (int i = 0; i < g; ++i)
                    pts.push_back({int(std::floor(-radius - 0.5 + (i + 0.5) * step + 0.5)),
                                   int(std::floor(-radius - 0.5 + (j + 0.5) * step + 0.5))});
            unique(pts);
            ensureCentre(pts, pts.size() + 1, rng);
            return pattern;
        }
        case PatternKind::Random: {
            // Partial Fisher-Yates over the window's pixel indices.
            std::vector<int> idx(windowSize);
            for (std::size_t i = 0; i < windowSize; ++i) idx[i] = int(i);
            for (std::size_t i = 0; i < target; ++i) {
                std::swap(idx[i], idx[i + rng.below(windowSize - i)]);
                pts.push_back({idx[i] % n - radius, idx[i] / n - radius});
            }
            break;
        }
        case PatternKind::Stratified: {
            const int g = int(std::ceil(std::sqrt(double(count))));
            const double step = double(n) / g;
            for (int j = 0; j < g; ++j)
                for (int i = 0; i < g; ++i)
                    pts.push_back(
                        {int(std::floor(-radius - 0.5 + (i + rng.uniformDouble()) * step + 0.5)),
                         int(std::floor(-radius - 0.5 + (j + rng.uniformDouble()) * step + 0.5))});
            for (Offset& o : pts) {
                o.dx = std::clamp(o.dx, -radius, radius);
                o.dy = std::clamp(o.dy, -radius, radius);
            }
            unique(pts);
            trimTo(pts, target, rng);
            break;
        }
    }
    ensureCentre(pts, target, rng);
    return pattern;
}

}  // namespace glint::denoise::detail
