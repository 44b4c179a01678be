#include "drape/viewer/offscreen_context.hpp"

#include <cstdio>
#include <stdexcept>

#include "gl.hpp"

// Mesa's OSMesa keeps a global list of framebuffers that it never frees (about 850 bytes per
// process, allocated inside OSMesaMakeCurrent). Tell LeakSanitizer, in sanitizer builds, that those
// are not ours; the hook is an ordinary unused function otherwise.
extern "C" const char* __lsan_default_suppressions() { return "leak:libOSMesa.so\n"; }

namespace drape::viewer {

namespace {

const char* severity_name(GLenum s) {
  switch (s) {
    case GL_DEBUG_SEVERITY_HIGH: return "high";
    case GL_DEBUG_SEVERITY_MEDIUM: return "medium";
    case GL_DEBUG_SEVERITY_LOW: return "low";
    default: return "notification";
  }
}

const char* type_name(GLenum t) {
  switch (t) {
    case GL_DEBUG_TYPE_ERROR: return "error";
    case GL_DEBUG_TYPE_DEPRECATED_BEHAVIOR: return "deprecated";
    case GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR: return "undefined-behaviour";
    case GL_DEBUG_TYPE_PORTABILITY: return "portability";
    case GL_DEBUG_TYPE_PERFORMANCE: return "performance";
    default: return "other";
  }
}

void GLAPIENTRY debug_callback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei length, const GLchar* message,
                               const void* user) {
  const auto* sink = static_cast<const GlDebugSink*>(user);
  (*sink)(severity_name(severity), type_name(type),
          std::string(message, length >= 0 ? std::size_t(length) : std::char_traits<char>::length(message)));
}

}  // namespace

void print_gl_debug_message(const std::string& severity, const std::string& type, const std::string& text) {
  if (severity == "notification") return;
  std::fprintf(stderr, "[gl %s %s] %s\n", severity.c_str(), type.c_str(), text.c_str());
}

OffscreenContext::OffscreenContext(GlDebugSink debug_sink) : m_sink(std::move(debug_sink)) {
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         4,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         5,
                         0};
  OSMesaContext ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!ctx) throw std::runtime_error("OSMesa could not create an OpenGL 4.5 core-profile context");
  m_context = ctx;
  if (!OSMesaMakeCurrent(ctx, m_placeholder, GL_UNSIGNED_BYTE, 4, 4)) {
    OSMesaDestroyContext(ctx);
    m_context = nullptr;
    throw std::runtime_error("OSMesaMakeCurrent failed");
  }
  if (m_sink) {
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);  // report inside the failing call, for usable backtraces
    glDebugMessageCallback(debug_callback, &m_sink);
    glDebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  }
}

OffscreenContext::~OffscreenContext() {
  if (m_sink) glDebugMessageCallback(nullptr, nullptr);
  if (m_context) {
    OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);  // release the context's framebuffer first
    OSMesaDestroyContext(static_cast<OSMesaContext>(m_context));
  }
}

std::string OffscreenContext::version() const { return reinterpret_cast<const char*>(glGetString(GL_VERSION)); }
std::string OffscreenContext::renderer() const { return reinterpret_cast<const char*>(glGetString(GL_RENDERER)); }

}  // namespace drape::viewer
