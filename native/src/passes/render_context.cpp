#include "passes/render_context.h"

namespace bounce {

void draw_fullscreen_triangle() {
  // Vertex arrays are not shared between contexts; each render thread has one context.
  thread_local GLuint empty_vertex_array = 0;
  if (!empty_vertex_array) glCreateVertexArrays(1, &empty_vertex_array);
  glBindVertexArray(empty_vertex_array);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

}  // namespace bounce
