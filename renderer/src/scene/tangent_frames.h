// Per-vertex tangents for normal mapping when an asset brings none, in the convention glTF
// prescribes (MikkTSpace): the tangent points along +u of the texture, the bitangent
// w · cross(normal, tangent) along +v, w = ±1 the handedness.
#pragma once

#include "scene/scene_data.h"

namespace glint::render::detail {

/// Fills mesh.tangents for the vertices of triangles [firstTriangle, lastTriangle) from their
/// positions, normals and texture coordinates (Glint's convention: v up). Each triangle's
/// tangent and bitangent (from its texture-coordinate derivatives) are summed into its corners
/// weighted by the corner's angle, then made orthogonal to the vertex normal (Gram–Schmidt); a
/// vertex shared by triangles of both handednesses (a mirrored texture) is split in two, as
/// MikkTSpace splits it. Vertices without a usable texture-space direction get any tangent
/// orthogonal to their normal. Needs normals and uvs; mesh.tangents is resized to the vertex
/// count (zero where not generated). `uvSet` 1 follows the second set (Mesh::uvs1, the normal
/// map's glTF texCoord) where the mesh has one.
void generateTangents(Mesh& mesh, std::size_t firstTriangle, std::size_t lastTriangle,
                      int uvSet = 0);

}  // namespace glint::render::detail
