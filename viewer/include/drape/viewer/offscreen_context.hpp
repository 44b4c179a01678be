#pragma once
/// \file offscreen_context.hpp
/// An OpenGL 4.5 core-profile context without a display: OSMesa (Mesa's software rasteriser), no
/// X, no GLFW. Rendering goes into framebuffer objects (see cloth_renderer.hpp); the context's own
/// buffer is a tiny placeholder.

#include <functional>
#include <string>

namespace drape::viewer {

/// Receives one KHR_debug message: severity ("high", "medium", "low", "notification"),
/// type ("error", "performance", ...) and text.
using GlDebugSink = std::function<void(const std::string& severity, const std::string& type, const std::string& text)>;

/// Writes "[gl <severity> <type>] <text>" to stderr; notifications are skipped.
void print_gl_debug_message(const std::string& severity, const std::string& type, const std::string& text);

class OffscreenContext {
 public:
  /// Creates the context and makes it current on this thread.
  /// \param debug_sink if set, a KHR_debug callback (core since GL 4.3) forwards GL errors and
  ///        warnings to it (the `--debug-gl` flag).
  /// \throws std::runtime_error if OSMesa cannot create a 4.5 core context.
  explicit OffscreenContext(GlDebugSink debug_sink = {});
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  /// "4.5 (Core Profile) Mesa 22.3.6", and the renderer ("llvmpipe ...").
  std::string version() const;
  std::string renderer() const;
  bool debug_enabled() const { return static_cast<bool>(m_sink); }

 private:
  void* m_context = nullptr;  // OSMesaContext
  unsigned char m_placeholder[4 * 4 * 4] = {};
  GlDebugSink m_sink;
};

}  // namespace drape::viewer
