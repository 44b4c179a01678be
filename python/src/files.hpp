#pragma once
// A scene file as the scene-and-files group (files.cpp) reads it and the rendering group
// (rendering.cpp) frames it. The only header of the module that includes the scene-file
// library (drape::scene_file).

#include <memory>

#include "drape/scene_file/build_scene.hpp"
#include "drape/scene_file/settings.hpp"

namespace drape::python {

/// A parsed and validated scene file with drape-render's flags applied, and the scene drape-render
/// would build from it.
struct SceneFile {
  std::shared_ptr<const drape::scene_file::Settings> settings;
  drape::scene_file::PreparedScene prepared;

  /// Frames of an offline run (drape-render's count: --frames, or enough to cover --duration).
  int frame_count() const;
};

}  // namespace drape::python
