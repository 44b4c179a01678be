#pragma once
/// \file solid_mesh.hpp
/// A rigid body as triangles to draw: the renderer draws it, the scene frames it (collider_mesh.hpp).

#include <vector>

namespace drape::viewer {

/// A rigid body to draw: triangles of three vertices each, `x y z nx ny nz` per vertex, in the
/// world frame; the normal is the triangle's (flat shading; either side is lit).
struct SolidMesh {
  std::vector<float> vertices;
  bool casts_shadow = true;  ///< its planar shadow is drawn on the floor (not for planes)
};

}  // namespace drape::viewer
