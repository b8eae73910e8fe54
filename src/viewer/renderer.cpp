#include "viewer/renderer.h"

#include "viewer/gl_util.h"

#include <Eigen/Core>

#include <string>

namespace freeform::viewer {
namespace {

const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec3 a_color;
uniform mat4 u_mvp;
uniform mat4 u_mv;
out vec3 v_position;  // eye space
out vec3 v_normal;    // eye space
out vec3 v_color;
void main() {
  v_position = (u_mv * vec4(a_position, 1.0)).xyz;
  v_normal = mat3(u_mv) * a_normal;  // the view matrix is a rigid motion
  v_color = a_color;
  gl_Position = u_mvp * vec4(a_position, 1.0);
}
)";

// Headlight: the light sits at the eye. Two-sided: back faces are lit like front faces.
const char* kFragmentShader = R"(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in vec3 v_color;
uniform float u_light;       // 1: shaded surface, 0: flat colour (wireframe pass)
uniform int u_wire;
uniform vec3 u_wire_color;
uniform int u_flat;          // 1: facet normal from the derivatives of the eye-space position
out vec4 frag_color;
void main() {
  if (u_wire != 0) { frag_color = vec4(u_wire_color, 1.0); return; }
  vec3 n = u_flat != 0 ? cross(dFdx(v_position), dFdy(v_position)) : v_normal;
  float len = length(n);
  n = len > 0.0 ? n / len : vec3(0.0, 0.0, 1.0);
  vec3 l = normalize(-v_position);
  float d = abs(dot(n, l));
  float s = pow(d, 48.0);
  vec3 c = v_color * (0.3 + 0.7 * d) + vec3(0.15 * s);
  frag_color = vec4(mix(v_color, c, u_light), 1.0);
}
)";

GLuint compile(GLenum type, const char* source) {
  const GLuint s = glCreateShader(type);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    glDeleteShader(s);
    throw RenderError(std::string("shader compilation failed: ") + log);
  }
  return s;
}

Eigen::Matrix4f to_float(const Eigen::Matrix4d& m) { return m.cast<float>(); }

void buffer(GLuint vbo, const std::vector<float>& data, GLenum usage) {
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(), usage);
}

}  // namespace

Renderer::Renderer() {
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048];
    glGetProgramInfoLog(program_, sizeof log, nullptr, log);
    glDeleteProgram(program_);
    throw RenderError(std::string("shader link failed: ") + log);
  }
  loc_mvp_ = glGetUniformLocation(program_, "u_mvp");
  loc_mv_ = glGetUniformLocation(program_, "u_mv");
  loc_light_ = glGetUniformLocation(program_, "u_light");
  loc_wire_ = glGetUniformLocation(program_, "u_wire");
  loc_wire_color_ = glGetUniformLocation(program_, "u_wire_color");
  loc_flat_ = glGetUniformLocation(program_, "u_flat");

  glGenVertexArrays(1, &vao_);
  GLuint b[4];
  glGenBuffers(4, b);
  vbo_position_ = b[0];
  vbo_normal_ = b[1];
  vbo_color_ = b[2];
  ebo_ = b[3];
  glBindVertexArray(vao_);
  const GLuint vbos[3] = {vbo_position_, vbo_normal_, vbo_color_};
  for (GLuint i = 0; i < 3; ++i) {
    glBindBuffer(GL_ARRAY_BUFFER, vbos[i]);
    glEnableVertexAttribArray(i);
    glVertexAttribPointer(i, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  }
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);  // recorded in the VAO
  glBindVertexArray(0);
  check_gl("renderer setup");
}

Renderer::~Renderer() {
  const GLuint b[4] = {vbo_position_, vbo_normal_, vbo_color_, ebo_};
  glDeleteBuffers(4, b);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(program_);
}

void Renderer::upload(const RenderScene& scene) {
  glBindVertexArray(vao_);
  buffer(vbo_position_, scene.positions, GL_DYNAMIC_DRAW);
  buffer(vbo_normal_, scene.normals, GL_DYNAMIC_DRAW);
  buffer(vbo_color_, scene.colors, GL_STATIC_DRAW);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.triangles.size() * sizeof(std::uint32_t)),
               scene.triangles.data(), GL_STATIC_DRAW);
  glBindVertexArray(0);
  n_indices_ = static_cast<int>(scene.triangles.size());
  n_vertices_ = scene.n_vertices();
  check_gl("mesh upload");
}

void Renderer::update_geometry(const RenderScene& scene) {
  const std::pair<int, int> all(0, scene.n_vertices());
  update_geometry(scene, std::span(&all, 1));
}

void Renderer::update_geometry(const RenderScene& scene, std::span<const std::pair<int, int>> ranges) {
  if (scene.n_vertices() != n_vertices_) throw RenderError("update_geometry: vertex count differs from the upload");
  for (const auto& [first, count] : ranges)
    if (first < 0 || count < 0 || first + count > n_vertices_) throw RenderError("update_geometry: vertex range outside the mesh");
  for (const auto& [vbo, data] : {std::pair(vbo_position_, &scene.positions), std::pair(vbo_normal_, &scene.normals)}) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    for (const auto& [first, count] : ranges)
      glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(3 * static_cast<std::size_t>(first) * sizeof(float)),
                      static_cast<GLsizeiptr>(3 * static_cast<std::size_t>(count) * sizeof(float)),
                      data->data() + 3 * static_cast<std::size_t>(first));
  }
  check_gl("geometry update");
}

void Renderer::update_colors(const RenderScene& scene) {
  if (scene.n_vertices() != n_vertices_) throw RenderError("update_colors: vertex count differs from the upload");
  glBindBuffer(GL_ARRAY_BUFFER, vbo_color_);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(scene.colors.size() * sizeof(float)), scene.colors.data());
  check_gl("colour update");
}

void Renderer::draw(const Camera& camera, int width, int height, const DrawOptions& options) const {
  glViewport(options.viewport_x, options.viewport_y, width, height);
  glClearColor(options.background[0], options.background[1], options.background[2], 1.0f);
  glClearDepth(1.0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (n_indices_ == 0) return;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LEQUAL);
  glDisable(GL_CULL_FACE);
  const Eigen::Matrix4f mv = to_float(camera.view());
  const Eigen::Matrix4f mvp = to_float(camera.projection(static_cast<double>(width) / height) * camera.view());
  glUseProgram(program_);
  glUniformMatrix4fv(loc_mvp_, 1, GL_FALSE, mvp.data());  // Eigen is column-major like GL
  glUniformMatrix4fv(loc_mv_, 1, GL_FALSE, mv.data());
  glUniform1f(loc_light_, 1.0f);
  glUniform1i(loc_wire_, 0);
  glUniform1i(loc_flat_, options.flat ? 1 : 0);
  glUniform3f(loc_wire_color_, options.wire_color[0], options.wire_color[1], options.wire_color[2]);
  glBindVertexArray(vao_);
  if (options.wireframe) {
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.0f, 1.0f);
  }
  glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  glDrawElements(GL_TRIANGLES, n_indices_, GL_UNSIGNED_INT, nullptr);
  if (options.wireframe) {
    glDisable(GL_POLYGON_OFFSET_FILL);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
    glUniform1i(loc_wire_, 1);
    glDrawElements(GL_TRIANGLES, n_indices_, GL_UNSIGNED_INT, nullptr);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
  }
  glBindVertexArray(0);
  glUseProgram(0);
  check_gl("draw");
}

}  // namespace freeform::viewer
