// The material kinds, one line each: X(Enum, object). detail::MaterialType (scene_data.h) is
// numbered in this order, and each object, a MaterialKind (bsdf.h), is defined in the kind's own
// file under materials/ (docs/architecture.md, "Adding a material kind").
#pragma once

#define GLINT_MATERIAL_KINDS(X)   \
    X(Diffuse, diffuseKind)       \
    X(Mirror, mirrorKind)         \
    X(Dielectric, dielectricKind) \
    X(Conductor, conductorKind)   \
    X(MetallicRoughness, metallicRoughnessKind)
