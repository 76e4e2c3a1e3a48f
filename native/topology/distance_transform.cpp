#include "distance_transform.h"

#include <algorithm>
#include <limits>

#include "common/parallel.h"

namespace bounce::topology {

namespace {

// One line of the transform: out[q] = min_p (q - p)² + f[p], with f[p] = kInfinite where the line has no
// feature. v, z: scratch (parabola apexes and the boundaries between them).
constexpr int64_t kInfinite = int64_t(1) << 40;

void transform_line(const int64_t* f, int64_t* out, int n, std::vector<int>& v, std::vector<double>& z) {
  v.resize(size_t(n));
  z.resize(size_t(n) + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    if (f[q] >= kInfinite) continue;
    double s = -std::numeric_limits<double>::infinity();
    while (k >= 0) {
      const int p = v[size_t(k)];
      s = (double(f[q] + int64_t(q) * q) - double(f[p] + int64_t(p) * p)) / (2.0 * (q - p));
      if (s > z[size_t(k)]) break;
      --k;
    }
    ++k;
    v[size_t(k)] = q;
    z[size_t(k)] = k == 0 ? -std::numeric_limits<double>::infinity() : s;
    z[size_t(k) + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) {
    std::fill_n(out, n, kInfinite);
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[size_t(j) + 1] < q) ++j;
    const int64_t d = q - v[size_t(j)];
    out[q] = d * d + f[v[size_t(j)]];
  }
}

}  // namespace

std::vector<uint32_t> squared_distance_transform(const VoxelGrid& grid) {
  const glm::ivec3 p = grid.shape.padded();
  const size_t count = grid.shape.padded_count();
  // In place, 32 bits a cell (no distance in a padded grid of kMaxResolution reaches 2^32); a line at a time in
  // 64 bits, UINT32_MAX standing for no feature yet.
  std::vector<uint32_t> field(count);
  for (size_t i = 0; i < count; ++i) field[i] = grid.solid[i] ? 0u : UINT32_MAX;

  // Along each axis in turn: lines are independent, so they run in parallel.
  const std::ptrdiff_t strides[3] = {1, p.x, std::ptrdiff_t(p.x) * p.y};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = p[axis];
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const size_t lines = size_t(p[a]) * size_t(p[b]);
    constexpr size_t kLinesPerTask = 64;  // scratch lines are allocated once per task
    parallel_for((lines + kLinesPerTask - 1) / kLinesPerTask, 0, 1, [&](size_t task) {
      const size_t begin = task * kLinesPerTask, end = std::min(lines, begin + kLinesPerTask);
      std::vector<int64_t> in(static_cast<size_t>(n)), out(static_cast<size_t>(n));
      std::vector<int> v;
      std::vector<double> z;
      for (size_t line = begin; line < end; ++line) {
        const std::ptrdiff_t base =
            std::ptrdiff_t(line % size_t(p[a])) * strides[a] + std::ptrdiff_t(line / size_t(p[a])) * strides[b];
        for (int q = 0; q < n; ++q) {
          const uint32_t f = field[size_t(base + q * strides[axis])];
          in[size_t(q)] = f == UINT32_MAX ? kInfinite : int64_t(f);
        }
        transform_line(in.data(), out.data(), n, v, z);
        for (int q = 0; q < n; ++q)
          field[size_t(base + q * strides[axis])] = uint32_t(std::min<int64_t>(out[size_t(q)], UINT32_MAX));
      }
    });
  }
  return field;
}

}  // namespace bounce::topology
