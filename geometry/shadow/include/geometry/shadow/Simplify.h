// Simplified stand-ins for finely tessellated meshes ("model no more than the scene needs").
//
// A mesh is simplified by half-edge collapses (each removes a vertex and moves its triangles onto
// a neighbour, so every kept vertex stays where it was), cheapest quadric error first, while
//   - every removed vertex stays within `tolerance` (world units) of a triangle of the simplified
//     surface whose normal is within `maxNormalDeviationDeg` of the original surface's normal
//     there (its area-weighted vertex normal), and every kept vertex's triangles stay within that
//     angle of its original normal (a one-sided Hausdorff bound on positions and normals at the
//     original vertices), and
//   - no triangle's normal turns by more than `maxNormalTurnDeg` in one collapse (no fold-overs).
// The stand-in replaces the mesh for every purpose (the image, the receivers, the casters), so
// shadows and the surfaces they fall on stay consistent: no self-shadowing from a caster that
// differs from its receiver.
//
// What that costs in visibility, to first order, for a light of smaller side L:
//   - in a shadow cast on something else, a silhouette moved by t, at d_l from the light and d_r
//     in front of the receiver, moves across the light by t (d_l + d_r) / d_r as the receiver
//     sees it: V changes by up to about t (d_l + d_r) / (d_r L), so by 2 t / L where the receiver
//     is as far behind the caster as the light is in front, and more close to contact;
//   - on the caster itself, where its own tangent plane cuts the light (the band around its
//     terminator), a normal off by an angle a moves that cut by a / alpha of the light, alpha the
//     angle the light subtends there: V changes by up to about a / alpha.
// simplifyOptionsFor() picks both bounds from one visibility error E: t = E L / 2 and a = E alpha,
// alpha taken at the mesh's farthest corner from the light (docs/benchmarks.md, "Simplified
// stand-ins").
//
// Meshes are left as they are, with the reason, where simplification would lose something:
// texture coordinates (seams and texels would move), more than one material, non-manifold
// topology (OpenMesh cannot hold it). Vertex normals are kept where a welded vertex had one
// normal; where its copies disagreed (a crease) it gets none and shades with its triangles' own.
#pragma once

#include <geometry/core/Types.h>

#include <cstddef>
#include <string>

namespace geometry {

struct Scene;


struct SimplifyOptions {
    float tolerance = 0.0f;              // world units, > 0
    float maxNormalDeviationDeg = 180.0f; // from the original normals, (0, 180]; 180 = no bound
    float maxNormalTurnDeg = 30.0f;      // per collapse, (0, 180)
};

struct SimplifiedMesh {
    MeshData mesh;      // the stand-in, or the input unchanged (see `skipped`)
    std::string skipped; // empty if simplified (even if nothing could be collapsed), else why not
};

// The bounds for a visibility error of about `visibilityError` (in (0, 1)) under `light`, for a
// mesh with `bounds` (see above). Throws InputError for an error outside (0, 1) or a light with
// no area.
SimplifyOptions simplifyOptionsFor(const Aabb& bounds, const RectLight& light, float visibilityError);

// Throws InputError for a tolerance that is not finite and positive, or a bad normal angle.
SimplifiedMesh simplifyMesh(const MeshData& mesh, const SimplifyOptions& options);

struct SimplifyStats {
    std::size_t meshes = 0;            // objects simplified
    std::size_t skipped = 0;           // objects left as they were (textured, non-manifold, ...)
    std::size_t trianglesBefore = 0;   // over the simplified objects
    std::size_t trianglesAfter = 0;
    std::string firstSkipReason;       // "objects[2] (torus): ..." of the first skipped one
};

// Every object of the scene through simplifyMesh, with simplifyOptionsFor(its bounds, the
// scene's light, visibilityError). No mesh loses all its triangles (a collapse that would is
// never legal); meshes below 8 triangles are left as they are.
SimplifyStats simplifyScene(Scene& scene, float visibilityError);

} // namespace geometry
