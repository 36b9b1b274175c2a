// Triangulation of one planar-ish polygon (an OBJ face of more than 3 corners) by ear clipping
// in its best-fit plane.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "vecmath.h"

namespace glint::render::detail {

/// The work budget of one polygon, in corners tested against candidate ears: kPolygonWorkBase
/// plus kPolygonWorkPerCorner per corner (about a second on one core). Common polygons, convex or
/// concave, need a few tests per corner; shapes whose ears span most of the polygon (a comb or
/// a spiral of 100k corners) would need n². OBJ faces, at most 255 corners (obj_scan.h), stay
/// far within it.
inline constexpr std::size_t kPolygonWorkBase = std::size_t(1) << 27;
inline constexpr std::size_t kPolygonWorkPerCorner = 128;

/// Triangulates the polygon `corners` (in order, either winding, the first corner not repeated at
/// the end) and appends its triangles to `triangles` as triples of corner indices, wound as the
/// polygon is. Ear clipping in the plane of the polygon's Newell normal, relative to its first
/// corner: correct for every simple polygon, convex or concave, and the same wherever it sits. A
/// simple polygon gets n − 2 triangles (flat ones at collinear corners) whose areas sum to its
/// area and which lie inside it; a polygon of zero area gets a fan; a self-intersecting one
/// (which has no correct triangulation) gets triangles covering its corners, without a
/// guarantee. Returns false, with `triangles` partly appended, when the polygon needs more work
/// than its budget.
bool triangulatePolygon(std::span<const Vec3> corners, std::vector<std::uint32_t>& triangles);

}  // namespace glint::render::detail
