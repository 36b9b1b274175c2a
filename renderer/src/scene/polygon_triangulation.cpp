// Ear clipping after Meisters 1975 ("Polygons have ears"), with the z-order hash of reflex
// candidates and the clean-up pass of Mapbox's earcut (Agafonkin 2016): an ear is tested only
// against the reflex corners whose z-order key lies within its bounding box's, so a large
// polygon costs about n log n in the common cases rather than n².
#include "scene/polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace glint::render::detail {

namespace {

struct Dvec3 {
    double x = 0.0, y = 0.0, z = 0.0;
};

Dvec3 crossD(const Dvec3& a, const Dvec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
double dotD(const Dvec3& a, const Dvec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// The corners of one polygon as a doubly linked ring in 2D, with a second list in z-order.
class EarClipper {
  public:
    EarClipper(std::vector<double> x, std::vector<double> y, std::vector<std::uint32_t>& out)
        : m_x(std::move(x)),
          m_y(std::move(y)),
          m_out(out),
          m_budget(kPolygonWorkPerCorner * m_x.size() + kPolygonWorkBase) {
        const int n = int(m_x.size());
        m_prev.resize(std::size_t(n));
        m_next.resize(std::size_t(n));
        for (int i = 0; i < n; ++i) {
            m_prev[std::size_t(i)] = (i + n - 1) % n;
            m_next[std::size_t(i)] = (i + 1) % n;
        }
        // Hash the corners along a z-order curve past 80 of them, as earcut does.
        if (n > 80) indexCurve();
    }

    /// Clips ears until fewer than 3 corners remain; false when the work budget ran out first.
    bool run() {
        int ear = 0, stop = 0;
        bool filtered = false;
        while (prev(ear) != next(ear)) {
            if (m_work > m_budget) return false;
            const int a = prev(ear), c = next(ear);
            if (m_hashed ? isEarHashed(ear) : isEar(ear)) {
                emit(a, ear, c);
                remove(ear);
                ear = stop = next(c);
                filtered = false;
                continue;
            }
            ear = c;
            if (ear != stop) continue;
            // A whole turn without an ear: drop duplicate and collinear corners, then try again.
            if (!filtered) {
                ear = stop = filterPoints(ear);
                filtered = true;
                continue;
            }
            // Still none: the polygon intersects itself (or rounding hides its ears). Clip the
            // first convex corner regardless, so that the loop ends.
            int f = ear;
            do {
                if (orient(prev(f), f, next(f)) > 0.0) break;
                f = next(f);
            } while (f != ear);
            const int fn = next(f);
            emit(prev(f), f, fn);
            remove(f);
            ear = stop = fn;
            filtered = false;
        }
        return true;
    }

  private:
    int prev(int i) const { return m_prev[std::size_t(i)]; }
    int next(int i) const { return m_next[std::size_t(i)]; }

    /// Twice the signed area of (a, b, c): > 0 for a counter-clockwise turn.
    double orient(int a, int b, int c) const {
        const auto A = std::size_t(a), B = std::size_t(b), C = std::size_t(c);
        return (m_x[B] - m_x[A]) * (m_y[C] - m_y[A]) - (m_y[B] - m_y[A]) * (m_x[C] - m_x[A]);
    }
    bool samePoint(int a, int b) const {
        return m_x[std::size_t(a)] == m_x[std::size_t(b)] &&
               m_y[std::size_t(a)] == m_y[std::size_t(b)];
    }
    /// p inside or on the counter-clockwise triangle (a, b, c), not at a or c.
    bool blocks(int a, int b, int c, int p) const {
        ++m_work;
        if (samePoint(p, a) || samePoint(p, c)) return false;
        if (orient(a, b, p) < 0.0 || orient(b, c, p) < 0.0 || orient(c, a, p) < 0.0) return false;
        // Only a reflex (or flat) corner can lie inside an ear of a simple polygon.
        return orient(prev(p), p, next(p)) <= 0.0;
    }

    bool isEar(int b) const {
        const int a = prev(b), c = next(b);
        if (orient(a, b, c) <= 0.0) return false;  // reflex or flat
        for (int p = next(c); p != a; p = next(p))
            if (blocks(a, b, c, p)) return false;
        return true;
    }

    bool isEarHashed(int b) const {
        const int a = prev(b), c = next(b);
        if (orient(a, b, c) <= 0.0) return false;
        const auto A = std::size_t(a), B = std::size_t(b), C = std::size_t(c);
        // Walk the z-order list both ways from b within the key range of the ear's box.
        const std::uint32_t minZ =
            zOrder(std::min({m_x[A], m_x[B], m_x[C]}), std::min({m_y[A], m_y[B], m_y[C]}));
        const std::uint32_t maxZ =
            zOrder(std::max({m_x[A], m_x[B], m_x[C]}), std::max({m_y[A], m_y[B], m_y[C]}));
        for (int p = m_prevZ[B]; p >= 0 && m_z[std::size_t(p)] >= minZ; p = m_prevZ[std::size_t(p)])
            if (p != a && p != c && blocks(a, b, c, p)) return false;
        for (int p = m_nextZ[B]; p >= 0 && m_z[std::size_t(p)] <= maxZ; p = m_nextZ[std::size_t(p)])
            if (p != a && p != c && blocks(a, b, c, p)) return false;
        return true;
    }

    /// Clips duplicate and collinear corners as flat triangles (dropping them instead would
    /// leave a T-junction where a neighbouring face uses the corner); returns a corner still in
    /// the ring.
    int filterPoints(int start) {
        int p = start, end = start;
        bool again;
        do {
            again = false;
            if (samePoint(p, next(p)) || orient(prev(p), p, next(p)) == 0.0) {
                const int before = prev(p);
                emit(before, p, next(p));
                remove(p);
                p = end = before;
                if (p == next(p)) break;
                again = true;
            } else {
                p = next(p);
            }
        } while (again || p != end);
        return end;
    }

    void emit(int a, int b, int c) {
        m_out.push_back(std::uint32_t(a));
        m_out.push_back(std::uint32_t(b));
        m_out.push_back(std::uint32_t(c));
    }

    /// Unlinks i from the ring and the z-order list (its own links stay, for the caller).
    void remove(int i) {
        const auto I = std::size_t(i);
        m_next[std::size_t(m_prev[I])] = m_next[I];
        m_prev[std::size_t(m_next[I])] = m_prev[I];
        if (!m_hashed) return;
        if (m_prevZ[I] >= 0) m_nextZ[std::size_t(m_prevZ[I])] = m_nextZ[I];
        if (m_nextZ[I] >= 0) m_prevZ[std::size_t(m_nextZ[I])] = m_prevZ[I];
    }

    /// The z-order (Morton) key of a point on a 32768² grid over the polygon's bounding box.
    std::uint32_t zOrder(double px, double py) const {
        auto spread = [](std::uint32_t v) {
            v = (v | (v << 8)) & 0x00FF00FFu;
            v = (v | (v << 4)) & 0x0F0F0F0Fu;
            v = (v | (v << 2)) & 0x33333333u;
            return (v | (v << 1)) & 0x55555555u;
        };
        const auto gx = std::uint32_t(std::clamp((px - m_minX) * m_invSize, 0.0, 32767.0));
        const auto gy = std::uint32_t(std::clamp((py - m_minY) * m_invSize, 0.0, 32767.0));
        return spread(gx) | (spread(gy) << 1);
    }

    void indexCurve() {
        const std::size_t n = m_x.size();
        m_minX = *std::min_element(m_x.begin(), m_x.end());
        m_minY = *std::min_element(m_y.begin(), m_y.end());
        const double size = std::max(*std::max_element(m_x.begin(), m_x.end()) - m_minX,
                                     *std::max_element(m_y.begin(), m_y.end()) - m_minY);
        if (!(size > 0.0)) return;
        m_invSize = 32767.0 / size;
        m_hashed = true;
        m_z.resize(n);
        for (std::size_t i = 0; i < n; ++i) m_z[i] = zOrder(m_x[i], m_y[i]);
        std::vector<int> order(n);
        std::iota(order.begin(), order.end(), 0);
        std::sort(order.begin(), order.end(),
                  [&](int a, int b) { return m_z[std::size_t(a)] < m_z[std::size_t(b)]; });
        m_prevZ.assign(n, -1);
        m_nextZ.assign(n, -1);
        for (std::size_t k = 0; k + 1 < n; ++k) {
            m_nextZ[std::size_t(order[k])] = order[k + 1];
            m_prevZ[std::size_t(order[k + 1])] = order[k];
        }
    }

    std::vector<double> m_x, m_y;
    std::vector<int> m_prev, m_next, m_prevZ, m_nextZ;
    std::vector<std::uint32_t> m_z;
    double m_minX = 0.0, m_minY = 0.0, m_invSize = 0.0;
    bool m_hashed = false;
    std::vector<std::uint32_t>& m_out;
    std::size_t m_budget;
    mutable std::size_t m_work = 0;  ///< corners tested against ears so far
};

}  // namespace

bool triangulatePolygon(std::span<const Vec3> corners, std::vector<std::uint32_t>& triangles) {
    const std::size_t n = corners.size();
    if (n < 3) return true;
    if (n == 3) {
        triangles.insert(triangles.end(), {0u, 1u, 2u});
        return true;
    }
    // Work relative to the first corner, in double (the difference of two floats is exact): the
    // result does not depend on where the polygon sits, only on its shape.
    std::vector<Dvec3> d(n);
    for (std::size_t i = 0; i < n; ++i)
        d[i] = {double(corners[i].x) - corners[0].x, double(corners[i].y) - corners[0].y,
                double(corners[i].z) - corners[0].z};

    // Newell's normal: twice the polygon's vector area, well defined for non-planar polygons
    // (Sutherland, Sproull and Schumacker 1974; Tampieri, Graphics Gems III, "Newell's method").
    Dvec3 normal;
    double extent = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const Dvec3& p = d[i];
        const Dvec3& q = d[(i + 1) % n];
        normal.x += (p.y - q.y) * (p.z + q.z);
        normal.y += (p.z - q.z) * (p.x + q.x);
        normal.z += (p.x - q.x) * (p.y + q.y);
        extent = std::max({extent, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    }
    const double len = std::sqrt(dotD(normal, normal));
    // Zero area (collinear or coincident corners, or loops that cancel): a fan of flat triangles.
    if (!(len > 1e-12 * extent * extent)) {
        for (std::uint32_t i = 1; i + 1 < n; ++i) triangles.insert(triangles.end(), {0u, i, i + 1});
        return true;
    }
    // Project onto the plane: u × v = normal, so the polygon turns counter-clockwise in (u, v).
    const Dvec3 nz{normal.x / len, normal.y / len, normal.z / len};
    const Dvec3 helper = std::fabs(nz.x) > 0.9 ? Dvec3{0.0, 1.0, 0.0} : Dvec3{1.0, 0.0, 0.0};
    Dvec3 u = crossD(helper, nz);
    const double ul = std::sqrt(dotD(u, u));
    u = {u.x / ul, u.y / ul, u.z / ul};
    const Dvec3 v = crossD(nz, u);
    std::vector<double> x(n), y(n);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = dotD(d[i], u);
        y[i] = dotD(d[i], v);
    }
    if (n == 4) {
        // A quad: split along the shorter diagonal (in float, as tinyobjloader did, so convex
        // quads keep their triangles) unless it lies outside (a concave quad), then the other.
        auto squared = [&](std::size_t a, std::size_t b) {
            const Vec3 e = corners[b] - corners[a];
            return dot(e, e);
        };
        auto ccw = [&](std::size_t a, std::size_t b, std::size_t c) {
            return (x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]) > 0.0;
        };
        const bool along02Valid = ccw(0, 1, 2) && ccw(0, 2, 3);
        const bool along13Valid = ccw(0, 1, 3) && ccw(1, 2, 3);
        const bool along02 = squared(0, 2) < squared(1, 3) ? along02Valid || !along13Valid
                                                           : !along13Valid && along02Valid;
        if (along02)
            triangles.insert(triangles.end(), {0u, 1u, 2u, 0u, 2u, 3u});
        else
            triangles.insert(triangles.end(), {0u, 1u, 3u, 1u, 2u, 3u});
        return true;
    }
    return EarClipper(std::move(x), std::move(y), triangles).run();
}

}  // namespace glint::render::detail
