#pragma once
/// A garment's mesh (built in double) in the scalar type a test steps it in.

#include "drape/core/cloth_mesh.hpp"

namespace drape::test {

template <class S>
ClothMesh<S> in_scalar(const ClothMesh<double>& m) {
  ClothMesh<S> out;
  out.positions = m.positions.cast<S>();
  out.triangles = m.triangles;
  out.rest_uv = m.rest_uv.cast<S>();
  out.groups = m.groups;
  return out;
}

}  // namespace drape::test
