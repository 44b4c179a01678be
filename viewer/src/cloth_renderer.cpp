#include "drape/viewer/cloth_renderer.hpp"

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

#include "gl.hpp"

namespace drape::viewer {

namespace {

const char* vertex_shader = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_grid;   // (i, j) grid coordinates of the node
uniform mat4 u_view_projection;
uniform int u_mode;            // 0 cloth, 1 floor, 2 a shadow on the floor, 3 a solid
uniform vec3 u_light;
uniform float u_floor_y;
out vec3 v_world;
out vec3 v_normal;
out vec2 v_grid;
void main() {
  vec3 p = a_position;
  // Planar shadow: slide the vertex along the light direction down onto the floor plane.
  if (u_mode == 2) p = vec3(p.x - u_light.x * (p.y - u_floor_y) / u_light.y, u_floor_y, p.z - u_light.z * (p.y - u_floor_y) / u_light.y);
  v_world = p;
  v_normal = a_normal;
  v_grid = a_grid;
  gl_Position = u_view_projection * vec4(p, 1.0);
}
)";

const char* fragment_shader = R"(#version 450 core
in vec3 v_world;
in vec3 v_normal;
in vec2 v_grid;
uniform int u_mode;            // 0 cloth, 1 floor, 2 shadow, 3 solid
uniform vec3 u_front;
uniform vec3 u_back;
uniform vec3 u_background;
uniform vec3 u_eye;
uniform vec3 u_light;          // unit vector towards the key light
uniform float u_pattern;       // strength of the woven pattern
uniform vec3 u_floor_centre;
uniform float u_floor_cell;
uniform float u_floor_fade;    // distance at which the floor has faded into the background
uniform vec3 u_solid;          // colour of the solids
out vec4 frag_colour;
void main() {
  vec3 to_eye = normalize(u_eye - v_world);
  if (u_mode == 3) {
    // A solid: its face normal, turned towards the eye (a plane is seen from either side).
    vec3 n = normalize(v_normal);
    if (dot(n, to_eye) < 0.0) n = -n;
    float key = max(dot(n, u_light), 0.0);
    float head = max(dot(n, to_eye), 0.0);
    frag_colour = vec4(min(u_solid * (0.16 + 0.62 * key + 0.32 * head), vec3(1.0)), 1.0);
    return;
  }
  if (u_mode != 0) {
    vec2 c = floor(v_world.xz / u_floor_cell);
    float checker = mod(c.x + c.y, 2.0);
    vec3 base = mix(vec3(0.62), vec3(0.70), checker);
    if (u_mode == 2) base *= 0.6;
    float lambert = 0.55 + 0.45 * max(u_light.y, 0.0);
    float fade = smoothstep(0.35 * u_floor_fade, u_floor_fade, length(v_world.xz - u_floor_centre.xz));
    frag_colour = vec4(mix(base * lambert, u_background, fade), 1.0);
    return;
  }
  // Lit on both sides: on a back face the outward normal is the flipped one.
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  vec3 base = gl_FrontFacing ? u_front : u_back;
  if (u_pattern > 0.0) {
    vec2 w = abs(fract(v_grid * 0.5) - 0.5);      // threads every second grid line
    base *= 1.0 - u_pattern * (1.0 - smoothstep(0.0, 0.12, min(w.x, w.y)));
  }
  float key = max(dot(n, u_light), 0.0);
  float head = max(dot(n, to_eye), 0.0);
  vec3 colour = base * (0.16 + 0.62 * key + 0.32 * head);
  frag_colour = vec4(min(colour, vec3(1.0)), 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw std::runtime_error(std::string("shader compilation failed: ") + log);
  }
  return s;
}

GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

}  // namespace

std::vector<std::array<float, 2>> ClothRenderer::grid_pattern(int nx, int ny) {
  std::vector<std::array<float, 2>> pattern(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) pattern[static_cast<std::size_t>(j * nx + i)] = {float(i), float(j)};
  return pattern;
}

ClothRenderer::ClothRenderer(int nx, int ny, const std::vector<std::array<int, 3>>& triangles,
                             const RenderSettings& settings)
    : ClothRenderer(grid_pattern(nx, ny), triangles, settings) {}

ClothRenderer::ClothRenderer(const std::vector<std::array<float, 2>>& pattern,
                             const std::vector<std::array<int, 3>>& triangles, const RenderSettings& settings)
    : m_settings(settings), m_node_count(static_cast<int>(pattern.size())), m_triangles(triangles) {
  if (settings.width < 1 || settings.height < 1) throw std::invalid_argument("ClothRenderer: image size must be >= 1");
  m_vertex_data.assign(static_cast<std::size_t>(m_node_count) * 6, 0.0f);

  // Shaders.
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex_shader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, fragment_shader);
  m_program = glCreateProgram();
  glAttachShader(m_program, vs);
  glAttachShader(m_program, fs);
  glLinkProgram(m_program);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint linked = 0;
  glGetProgramiv(m_program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char log[2048] = {};
    glGetProgramInfoLog(m_program, sizeof log, nullptr, log);
    throw std::runtime_error(std::string("shader link failed: ") + log);
  }

  // Cloth: dynamic positions + normals, static grid coordinates, static indices.
  glGenVertexArrays(1, &m_vao);
  glBindVertexArray(m_vao);
  glGenBuffers(1, &m_dynamic_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m_dynamic_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_vertex_data.size() * sizeof(float)), nullptr,
               GL_DYNAMIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(0));
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  static_assert(sizeof(std::array<float, 2>) == 2 * sizeof(float), "pattern coordinates must be tightly packed");
  const std::vector<std::array<float, 2>>& grid = pattern;
  glGenBuffers(1, &m_static_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m_static_vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(grid.size() * sizeof(std::array<float, 2>)), grid.data(),
               GL_STATIC_DRAW);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(2);
  glGenBuffers(1, &m_ebo);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_ebo);  // recorded in the VAO
  static_assert(sizeof(std::array<int, 3>) == 3 * sizeof(GLuint), "triangles must be tightly packed");
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(m_triangles.size() * sizeof(std::array<int, 3>)),
               m_triangles.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);

  // Floor: one quad, positioned in render() from the camera.
  glGenVertexArrays(1, &m_floor_vao);
  glBindVertexArray(m_floor_vao);
  glGenBuffers(1, &m_floor_vbo);
  glBindBuffer(GL_ARRAY_BUFFER, m_floor_vbo);
  glBufferData(GL_ARRAY_BUFFER, 4 * 3 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), reinterpret_cast<void*>(0));
  glEnableVertexAttribArray(0);
  glVertexAttrib3f(1, 0.0f, 1.0f, 0.0f);
  glVertexAttrib2f(2, 0.0f, 0.0f);
  glBindVertexArray(0);

  // Multisampled target, resolved into a single-sample one for read-back.
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  m_samples = std::max(1, std::min(settings.samples, int(max_samples)));
  const int w = settings.width, h = settings.height;
  glGenRenderbuffers(1, &m_msaa_colour);
  glBindRenderbuffer(GL_RENDERBUFFER, m_msaa_colour);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples > 1 ? m_samples : 0, GL_RGBA8, w, h);
  glGenRenderbuffers(1, &m_msaa_depth);
  glBindRenderbuffer(GL_RENDERBUFFER, m_msaa_depth);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, m_samples > 1 ? m_samples : 0, GL_DEPTH_COMPONENT24, w, h);
  glGenFramebuffers(1, &m_msaa_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_msaa_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_msaa_colour);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, m_msaa_depth);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("multisampled framebuffer incomplete");
  glGenRenderbuffers(1, &m_resolve_colour);
  glBindRenderbuffer(GL_RENDERBUFFER, m_resolve_colour);
  glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
  glGenFramebuffers(1, &m_resolve_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, m_resolve_fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, m_resolve_colour);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("resolve framebuffer incomplete");
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  m_readback.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
}

ClothRenderer::~ClothRenderer() {
  glDeleteFramebuffers(1, &m_resolve_fbo);
  glDeleteRenderbuffers(1, &m_resolve_colour);
  glDeleteFramebuffers(1, &m_msaa_fbo);
  glDeleteRenderbuffers(1, &m_msaa_depth);
  glDeleteRenderbuffers(1, &m_msaa_colour);
  if (m_solid_vao != 0) {
    glDeleteBuffers(1, &m_solid_vbo);
    glDeleteVertexArrays(1, &m_solid_vao);
  }
  glDeleteBuffers(1, &m_floor_vbo);
  glDeleteVertexArrays(1, &m_floor_vao);
  glDeleteBuffers(1, &m_ebo);
  glDeleteBuffers(1, &m_static_vbo);
  glDeleteBuffers(1, &m_dynamic_vbo);
  glDeleteVertexArrays(1, &m_vao);
  glDeleteProgram(m_program);
}

void ClothRenderer::update(const Eigen::Ref<const Eigen::Matrix3Xf>& x) {
  if (x.cols() != m_node_count)
    throw std::invalid_argument("ClothRenderer::update: expected " + std::to_string(m_node_count) + " positions, got " +
                                std::to_string(x.cols()));
  // Area-weighted vertex normals: the sum of the (unnormalised) normals of the adjacent triangles.
  Eigen::Map<Eigen::Matrix<float, 6, Eigen::Dynamic>> v(m_vertex_data.data(), 6, m_node_count);
  v.topRows<3>() = x;
  v.bottomRows<3>().setZero();
  for (const auto& t : m_triangles) {
    const Eigen::Vector3f a = x.col(t[0]), b = x.col(t[1]), c = x.col(t[2]);
    const Eigen::Vector3f n = (b - a).cross(c - a);
    for (int k : t) v.block<3, 1>(3, k) += n;
  }
  for (int i = 0; i < m_node_count; ++i) {
    const float len = v.block<3, 1>(3, i).norm();
    if (len > 0)
      v.block<3, 1>(3, i) /= len;
    else
      v.block<3, 1>(3, i) = Eigen::Vector3f::UnitY();
  }
  glBindBuffer(GL_ARRAY_BUFFER, m_dynamic_vbo);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(m_vertex_data.size() * sizeof(float)),
                  m_vertex_data.data());
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void ClothRenderer::set_solids(const std::vector<SolidMesh>& solids) {
  std::vector<float> data;
  m_solids.clear();
  for (const SolidMesh& s : solids) {
    if (s.vertices.size() % 6 != 0)
      throw std::invalid_argument("ClothRenderer::set_solids: 6 floats per vertex expected");
    m_solids.push_back({int(data.size() / 6), int(s.vertices.size() / 6), s.casts_shadow});
    data.insert(data.end(), s.vertices.begin(), s.vertices.end());
  }
  if (m_solid_vao == 0) {
    glGenVertexArrays(1, &m_solid_vao);
    glBindVertexArray(m_solid_vao);
    glGenBuffers(1, &m_solid_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, m_solid_vbo);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(0));
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), reinterpret_cast<void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(0);
    glEnableVertexAttribArray(1);
    glBindVertexArray(0);
  }
  glBindBuffer(GL_ARRAY_BUFFER, m_solid_vbo);
  if (data.size() > m_solid_capacity) {
    m_solid_capacity = data.size();
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), GL_DYNAMIC_DRAW);
  } else if (!data.empty()) {
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data());
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
}

Image ClothRenderer::render() {
  const int w = m_settings.width, h = m_settings.height;
  const Camera& cam = m_camera;
  glBindFramebuffer(GL_FRAMEBUFFER, m_msaa_fbo);
  glViewport(0, 0, w, h);
  glDisable(GL_CULL_FACE);  // the cloth is one surface seen from both sides
  glEnable(GL_DEPTH_TEST);
  if (m_samples > 1) glEnable(GL_MULTISAMPLE);
  const Eigen::Vector3f bg = m_settings.background;
  glClearColor(bg.x(), bg.y(), bg.z(), 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  glUseProgram(m_program);
  const Eigen::Matrix4f vp = cam.projection * cam.view;
  glUniformMatrix4fv(uniform(m_program, "u_view_projection"), 1, GL_FALSE, vp.data());  // column-major, as GL wants
  glUniform3fv(uniform(m_program, "u_front"), 1, m_settings.front_colour.data());
  glUniform3fv(uniform(m_program, "u_back"), 1, m_settings.back_colour.data());
  glUniform3fv(uniform(m_program, "u_background"), 1, bg.data());
  glUniform3fv(uniform(m_program, "u_eye"), 1, cam.eye.data());
  const Eigen::Vector3f light = Eigen::Vector3f(0.3f, 1.0f, 0.45f).normalized();
  glUniform3fv(uniform(m_program, "u_light"), 1, light.data());
  glUniform1f(uniform(m_program, "u_pattern"), m_settings.pattern ? 0.12f : 0.0f);

  // A camera below the floor (negative elevation) would see only the floor's underside: skip it.
  if (m_settings.floor && cam.eye.y() > cam.floor_height) {
    const float r = 6.0f * cam.scene_radius;
    const float y = cam.floor_height;
    const float cx = cam.target.x(), cz = cam.target.z();
    const float quad[12] = {cx - r, y, cz - r, cx + r, y, cz - r, cx - r, y, cz + r, cx + r, y, cz + r};
    glBindBuffer(GL_ARRAY_BUFFER, m_floor_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof quad, quad);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glUniform1i(uniform(m_program, "u_mode"), 1);
    glUniform3fv(uniform(m_program, "u_floor_centre"), 1, cam.target.data());
    glUniform1f(uniform(m_program, "u_floor_cell"), m_settings.floor_cell);
    glUniform1f(uniform(m_program, "u_floor_fade"), r);
    glUniform1f(uniform(m_program, "u_floor_y"), y);
    glBindVertexArray(m_floor_vao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    // The cloth's shadow, flattened onto the floor; drawn without depth test (it lies on the
    // floor, and the cloth drawn next still tests against the floor's depth).
    glUniform1i(uniform(m_program, "u_mode"), 2);
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(m_vao);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_triangles.size() * 3), GL_UNSIGNED_INT, nullptr);
    if (!m_solids.empty()) {  // the solids' shadows, the same way
      glBindVertexArray(m_solid_vao);
      for (const SolidRange& solid : m_solids)
        if (solid.shadow) glDrawArrays(GL_TRIANGLES, solid.first, solid.count);
    }
    glEnable(GL_DEPTH_TEST);
  }
  if (!m_solids.empty()) {
    glUniform1i(uniform(m_program, "u_mode"), 3);
    glUniform3fv(uniform(m_program, "u_solid"), 1, m_settings.solid_colour.data());
    glBindVertexArray(m_solid_vao);
    for (const SolidRange& solid : m_solids) glDrawArrays(GL_TRIANGLES, solid.first, solid.count);
  }
  glUniform1i(uniform(m_program, "u_mode"), 0);
  glBindVertexArray(m_vao);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m_triangles.size() * 3), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);

  // Resolve the samples and read back (GL rows are bottom-up).
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_msaa_fbo);
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_resolve_fbo);
  glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, m_resolve_fbo);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, m_readback.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  Image image;
  image.width = w;
  image.height = h;
  image.rgb.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
  for (int y = 0; y < h; ++y) {
    const unsigned char* src =
        m_readback.data() + static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) * 4;
    unsigned char* dst = image.rgb.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w) * 3;
    for (int x = 0; x < w; ++x) {
      dst[3 * x] = src[4 * x];
      dst[3 * x + 1] = src[4 * x + 1];
      dst[3 * x + 2] = src[4 * x + 2];
    }
  }
  return image;
}

}  // namespace drape::viewer
