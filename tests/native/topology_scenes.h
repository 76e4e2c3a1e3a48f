// Synthetic architecture for the topology tests: closed rooms made of thin walls (quads, two triangles each).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

namespace bounce::test {

// Triangle soup builder.
struct Soup {
  std::vector<glm::vec3> vertices;

  // The axis-aligned rectangle lo..hi, flat along `axis` (lo[axis] == hi[axis]).
  Soup& quad(glm::vec3 lo, glm::vec3 hi, int axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    glm::vec3 c[4] = {lo, lo, lo, lo};
    c[1][u] = hi[u];
    c[2][u] = hi[u], c[2][v] = hi[v];
    c[3][v] = hi[v];
    for (int i : {0, 1, 2, 0, 2, 3}) vertices.push_back(c[i]);
    return *this;
  }
  // The six faces of the box lo..hi.
  Soup& box(glm::vec3 lo, glm::vec3 hi) {
    for (int axis = 0; axis < 3; ++axis) {
      glm::vec3 top = hi, bottom = lo;
      top[axis] = lo[axis];
      quad(lo, top, axis);
      bottom[axis] = hi[axis];
      quad(bottom, hi, axis);
    }
    return *this;
  }
  // A wall in the plane `axis` = at, over lo..hi of the other axes, with a rectangular opening o_lo..o_hi.
  Soup& wall_with_opening(int axis, float at, glm::vec3 lo, glm::vec3 hi, glm::vec3 o_lo, glm::vec3 o_hi) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    lo[axis] = hi[axis] = o_lo[axis] = o_hi[axis] = at;
    const auto piece = [&](float u0, float u1, float v0, float v1) {
      if (u1 <= u0 || v1 <= v0) return;
      glm::vec3 a = lo, b = lo;
      a[u] = u0, a[v] = v0, b[u] = u1, b[v] = v1;
      quad(a, b, axis);
    };
    piece(lo[u], o_lo[u], lo[v], hi[v]);
    piece(o_hi[u], hi[u], lo[v], hi[v]);
    piece(o_lo[u], o_hi[u], lo[v], o_lo[v]);
    piece(o_lo[u], o_hi[u], o_hi[v], hi[v]);
    return *this;
  }
};

// A closed 10 x 6 x 4 room.
inline Soup closed_box() { return Soup().box({0, 0, 0}, {10, 6, 4}); }

// Two 10 x 10 x 4 rooms side by side along x, joined by a doorway 2 wide and 3 high in the wall x = 10,
// centred in y.
inline constexpr glm::vec3 kDoorLo{10.0f, 4.0f, 0.0f}, kDoorHi{10.0f, 6.0f, 3.0f};
inline Soup two_rooms() {
  Soup s;
  s.box({0, 0, 0}, {20, 10, 4});
  s.wall_with_opening(0, 10.0f, {0, 0, 0}, {0, 10, 4}, kDoorLo, kDoorHi);
  return s;
}

// The same two rooms with a solid middle wall: no light can pass from one to the other.
inline Soup two_closed_rooms() {
  Soup s;
  s.box({0, 0, 0}, {20, 10, 4});
  s.quad({10, 0, 0}, {10, 10, 4}, 0);
  return s;
}

// The same two rooms with the doorway widened to 4 x 3 and, with `fins`, filled with a grille of vertical fins 0.2
// deep every 0.1 (y = 3.05 ... 6.95): light passes between the fins where it travels within 27 degrees of the x
// axis, but the gaps are narrower than a voxel of the default grid (about 0.16), which closes them: no gate joins
// the rooms. The floor is in 1 x 1 tiles, so that Forward Light Cuts' VPLs resolve a small lit spot on it.
inline Soup two_rooms_with_grille(bool fins = true) {
  Soup s;
  s.box({0, 0, 0}, {20, 10, 4});
  s.vertices.erase(s.vertices.begin() + 24, s.vertices.begin() + 30);  // the floor (z = 0), again in 1 x 1 tiles
  for (int x = 0; x < 20; ++x)
    for (int y = 0; y < 10; ++y) s.quad({float(x), float(y), 0.0f}, {float(x + 1), float(y + 1), 0.0f}, 2);
  s.wall_with_opening(0, 10.0f, {0, 0, 0}, {0, 10, 4}, {10.0f, 3.0f, 0.0f}, {10.0f, 7.0f, 3.0f});
  for (int fin = 0; fin < (fins ? 40 : 0); ++fin) {
    const float y = 3.05f + 0.1f * float(fin);
    s.quad({9.9f, y, 0.0f}, {10.1f, y, 3.0f}, 1);
  }
  return s;
}

// A closed 6 x 4 x 3 room with a window 2 wide and 1.2 high in its wall y = 0, on a 40 x 40 ground: a sun outside
// shines in through the window, and most of what is inside is lit indirectly. With `blinds`, slats 3 cm thick and
// 10 cm deep every 15 cm across the window, just outside it, whose gaps the topology's grid closes.
inline constexpr glm::vec3 kWindowLo{2.0f, 0.0f, 1.0f}, kWindowHi{4.0f, 0.0f, 2.2f};
inline Soup room_with_window(bool blinds = false) {
  Soup s;
  s.quad({-20, -20, 0}, {20, 20, 0}, 2);  // the ground, the room's floor included
  s.quad({0, 0, 3}, {6, 4, 3}, 2);        // ceiling
  s.quad({0, 0, 0}, {0, 4, 3}, 0);
  s.quad({6, 0, 0}, {6, 4, 3}, 0);
  s.quad({0, 4, 0}, {6, 4, 3}, 1);
  s.wall_with_opening(1, 0.0f, {0, 0, 0}, {6, 0, 3}, kWindowLo, kWindowHi);
  for (float z = kWindowLo.z + 0.1f; blinds && z < kWindowHi.z; z += 0.15f)
    s.box({kWindowLo.x, -0.1f, z}, {kWindowHi.x, 0.0f, z + 0.03f});
  return s;
}

// The budget's sunlit interior in small (benchmarks/sunlit_interior_scene.py, furniture left out): a 6 x 5 x 2.8 room
// of closed boxes 0.2 thick, a window kDeepWindowLo..kDeepWindowHi in its wall y = 0 closed by eleven horizontal
// slats 3 cm thick and 8 cm deep in the middle of the wall's depth, on a 14 x 14 ground: at the default grid (11 cm
// voxels) the slats' 8.8 cm gaps are closed.
inline constexpr glm::vec3 kDeepWindowLo{1.5f, 0.0f, 0.9f}, kDeepWindowHi{3.5f, 0.0f, 2.2f};
inline Soup room_with_deep_blinds() {
  constexpr float kWall = 0.2f, kHeight = 2.8f, kThick = 0.03f, kDeep = 0.08f;
  constexpr int kSlats = 11;
  const glm::vec3 lo = kDeepWindowLo, hi = kDeepWindowHi;
  Soup s;
  s.quad({-4.0f, -4.5f, -0.05f}, {10.0f, 9.5f, -0.05f}, 2);    // the ground, under the floor's box too
  s.box({-kWall, -kWall, -kWall}, {6 + kWall, 5 + kWall, 0});  // floor
  s.box({-kWall, -kWall, kHeight}, {6 + kWall, 5 + kWall, kHeight + kWall});
  s.box({-kWall, 0, 0}, {0, 5, kHeight});
  s.box({6, 0, 0}, {6 + kWall, 5, kHeight});
  s.box({-kWall, 5, 0}, {6 + kWall, 5 + kWall, kHeight});
  s.box({-kWall, -kWall, 0}, {lo.x, 0, kHeight});  // the window's wall, around the opening
  s.box({hi.x, -kWall, 0}, {6 + kWall, 0, kHeight});
  s.box({lo.x, -kWall, 0}, {hi.x, 0, lo.z});
  s.box({lo.x, -kWall, hi.z}, {hi.x, 0, kHeight});
  const float pitch = (hi.z - lo.z) / float(kSlats);
  for (int i = 0; i < kSlats; ++i) {
    const float z = lo.z + (float(i) + 0.5f) * pitch;
    s.box({lo.x, -kWall / 2 - kDeep / 2, z - kThick / 2}, {hi.x, -kWall / 2 + kDeep / 2, z + kThick / 2});
  }
  return s;
}

// A square ring corridor: a closed 12 x 12 x 3 hall with a closed 6 x 6 block in its middle.
inline Soup ring_corridor() {
  Soup s;
  s.box({0, 0, 0}, {12, 12, 3});
  s.box({3, 3, 0}, {9, 9, 3});
  return s;
}

// A U-shaped corridor 2 wide: a closed 12 x 10 x 3 hall with a 8 x 8 block against one long side, so the
// corridor runs up x = 0..2, across y = 8..10 and down x = 10..12.
inline Soup u_corridor() {
  Soup s;
  s.box({0, 0, 0}, {12, 10, 3});
  s.box({2, 0, 0}, {10, 8, 3});
  return s;
}

// A Cornell-like box, 2 x 2 x 2, open at y = 0, empty.
inline Soup open_box_walls() {
  Soup s;
  s.quad({-1, 0, 0}, {1, 2, 0}, 2);  // floor
  s.quad({-1, 0, 2}, {1, 2, 2}, 2);  // ceiling
  s.quad({-1, 2, 0}, {1, 2, 2}, 1);  // back
  s.quad({-1, 0, 0}, {-1, 2, 2}, 0);
  s.quad({1, 0, 0}, {1, 2, 2}, 0);
  return s;
}

// The open box with a short and a tall block inside: the open side joins the room to the empty space around it, and
// the skeleton branches into that space and into the room's edges.
inline Soup open_box() {
  Soup s = open_box_walls();
  s.box({0.1f, 0.3f, 0.0f}, {0.7f, 0.9f, 0.6f});
  s.box({-0.7f, 0.9f, 0.0f}, {-0.1f, 1.5f, 1.2f});
  return s;
}

// Blocks standing on a 200 m ground, as the budget's open ground (benchmarks/open_ground_scene.py) has them: the
// ground sets the grid, so the air about the blocks is a slab a few voxels thick, which the skeleton splits into
// clusters whose shared boundaries are no openings.
inline Soup blocks_on_open_ground() {
  Soup s;
  s.quad({-100, -100, 0}, {100, 100, 0}, 2);
  s.box({-1.0f, -1.0f, 0.0f}, {1.0f, 1.0f, 2.0f});
  s.box({3.0f, 0.5f, 0.0f}, {4.0f, 3.5f, 1.0f});
  s.box({-3.6f, 2.4f, 0.0f}, {-2.4f, 3.6f, 4.0f});
  s.box({0.3f, -4.2f, 0.0f}, {2.7f, -1.8f, 2.4f});
  return s;
}

}  // namespace bounce::test
