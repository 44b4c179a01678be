#pragma once
// A scene file as the scene-and-files group (files.cpp) reads it and the rendering group
// (rendering.cpp) frames it. The only header of the module that includes drape-render's
// scene-file reader.

#include <memory>

#include "scene_setup.hpp"

namespace drape::python {

/// A parsed and validated scene file with drape-render's flags applied, and the scene drape-render
/// would build from it.
struct SceneFile {
  std::shared_ptr<const drape::render::Settings> settings;
  drape::render::PreparedScene prepared;

  /// Frames of an offline run (drape-render's count: --frames, or enough to cover --duration).
  int frame_count() const;
};

}  // namespace drape::python
