#pragma once
/// \file cloth_renderer.hpp
/// Draws the cloth mesh offscreen (needs a current OffscreenContext).
///
/// GL resources: one vertex array object; positions and normals interleaved in a
/// `GL_DYNAMIC_DRAW` buffer rewritten every frame with `glBufferSubData`; grid coordinates in a
/// static buffer; the triangles of `Grid::triangles()` in a static `GL_ELEMENT_ARRAY_BUFFER`.
/// Per-vertex normals are recomputed on the CPU each frame (area-weighted face normals).
/// Shading: Lambert with a key light from above plus a head light, lit on both sides (the normal
/// is flipped on back faces, `gl_FrontFacing`), one colour per side; face culling is disabled.
/// A checkered floor below the cloth gives depth. Rigid bodies (the colliders) can be added as
/// solids: triangle meshes in one colour, flat shaded, casting shadows on the floor like the cloth.
/// Rendering goes into a multisampled framebuffer object that is resolved and read back.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "drape/viewer/camera.hpp"
#include "drape/viewer/image.hpp"
#include "drape/viewer/solid_mesh.hpp"

namespace drape::viewer {

struct RenderSettings {
  int width = 640;
  int height = 480;
  int samples = 4;          ///< MSAA samples (clamped to what the implementation offers)
  bool floor = true;        ///< checkered floor plane below the cloth
  bool pattern = true;      ///< faint woven pattern on the cloth (off: pure Lambert, for tests)
  float floor_cell = 0.4f;  ///< side of the floor's checker squares (m)
  Eigen::Vector3f front_colour{0.80f, 0.28f, 0.20f};  ///< side whose normal is +y at rest (top)
  Eigen::Vector3f back_colour{0.20f, 0.42f, 0.78f};   ///< underside
  Eigen::Vector3f background{0.93f, 0.94f, 0.96f};
  Eigen::Vector3f solid_colour{0.70f, 0.71f, 0.69f};  ///< the solids (colliders): a neutral grey
};

class ClothRenderer {
 public:
  /// \param triangles vertex ids (Grid::triangles()); `node_count` vertices, grid `nx x ny` (for
  ///        the pattern's coordinates, node id = j * nx + i).
  /// \throws std::runtime_error if a shader fails to compile or the framebuffer is incomplete.
  ClothRenderer(int nx, int ny, const std::vector<std::array<int, 3>>& triangles, const RenderSettings& settings);
  /// Any triangle mesh, e.g. several cloths drawn as one: `pattern` holds each vertex's grid
  /// coordinates (i, j) for the checker pattern, one entry per vertex.
  ClothRenderer(const std::vector<std::array<float, 2>>& pattern, const std::vector<std::array<int, 3>>& triangles,
                const RenderSettings& settings);
  ~ClothRenderer();

  /// The pattern coordinates of an nx x ny grid (node id = j * nx + i).
  static std::vector<std::array<float, 2>> grid_pattern(int nx, int ny);
  ClothRenderer(const ClothRenderer&) = delete;
  ClothRenderer& operator=(const ClothRenderer&) = delete;

  void set_camera(const Camera& camera) { m_camera = camera; }
  const Camera& camera() const { return m_camera; }

  /// Uploads new positions (`3 x node_count`), recomputing the normals.
  void update(const Eigen::Ref<const Eigen::Matrix3Xf>& positions);
  template <class Derived>
  void update_positions(const Eigen::MatrixBase<Derived>& positions) {
    m_positions_f = positions.template cast<float>();
    update(m_positions_f);
  }

  /// The solids drawn with the cloth from now on (replacing the previous ones); none at first.
  void set_solids(const std::vector<SolidMesh>& solids);

  /// Draws the last uploaded positions and reads the image back.
  Image render();

  const RenderSettings& settings() const { return m_settings; }
  int samples() const { return m_samples; }  ///< MSAA samples actually used

 private:
  RenderSettings m_settings;
  Camera m_camera;
  int m_node_count;
  int m_samples = 1;
  std::vector<std::array<int, 3>> m_triangles;
  std::vector<float> m_vertex_data;  // x y z nx ny nz per vertex
  Eigen::Matrix3Xf m_positions_f;
  unsigned m_program = 0, m_vao = 0, m_dynamic_vbo = 0, m_static_vbo = 0, m_ebo = 0;
  unsigned m_floor_vao = 0, m_floor_vbo = 0;
  unsigned m_solid_vao = 0, m_solid_vbo = 0;  // created by the first set_solids()
  std::size_t m_solid_capacity = 0;           // floats the solid buffer holds
  struct SolidRange {
    int first, count;  // vertices
    bool shadow;
  };
  std::vector<SolidRange> m_solids;
  unsigned m_msaa_fbo = 0, m_msaa_colour = 0, m_msaa_depth = 0, m_resolve_fbo = 0, m_resolve_colour = 0;
  std::vector<unsigned char> m_readback;
};

}  // namespace drape::viewer
