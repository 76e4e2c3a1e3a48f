#include "passes/render_context.h"

namespace bounce {

GLuint empty_vertex_array() {
  // Vertex arrays are not shared between contexts; each render thread has one context.
  thread_local GLuint vertex_array = 0;
  if (!vertex_array) glCreateVertexArrays(1, &vertex_array);
  return vertex_array;
}

void draw_fullscreen_triangle() {
  glBindVertexArray(empty_vertex_array());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace bounce
