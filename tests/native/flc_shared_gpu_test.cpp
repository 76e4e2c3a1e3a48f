// The Forward Light Cuts functions of shaders/flc/flc_shared.glsl, run by a compute shader and by the host
// (flc_math.h): both must give the same levels, the same hashes and the same values to float precision.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "gl/egl_context.h"
#include "gl/shader.h"
#include "passes/flc/flc_math.h"

namespace bounce::test {
namespace {

struct Case {  // std430 mirror of `Case` below
  float u, area, d, s0, mu, d0, u1, u2;
  int32_t k, levels;
  uint32_t random;
  float inverse_cumulative_n;
};

struct Result {
  float level, partition_value, inverse_cumulative, support;
  float point[4];
  float oversize_weight, unit;
  uint32_t triangle_random, padding;
};

constexpr const char* kShader = R"(#include "common/random.glsl"
#include "flc/flc_shared.glsl"
layout(local_size_x = 64) in;
struct Case {
  float u, area, d, s0, mu, d0, u1, u2;
  int k, levels;
  uint random;
  float inverse_cumulative_n;
};
struct Result {
  float level, partition_value, inverse_cumulative, support;
  vec4 point;
  float oversize_weight, unit;
  uint triangle_random, padding;
};
layout(std430, binding = 0) readonly buffer Cases { Case cases[]; };
layout(std430, binding = 1) writeonly buffer Results { Result results[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(cases.length())) return;
  Case c = cases[i];
  results[i].level = float(flc_level(c.u, c.area, c.s0, c.mu, c.levels));
  results[i].partition_value = flc_partition(c.d, c.k, c.levels, c.d0, c.mu);
  results[i].inverse_cumulative = flc_inverse_cumulative_area(c.s0, c.mu, c.levels);
  results[i].support = flc_support_distance(c.k, c.levels, c.d0, c.mu);
  results[i].point = vec4(flc_triangle_point(c.u1, c.u2), 0.0);
  results[i].oversize_weight = flc_oversize_weight(c.area, c.inverse_cumulative_n);
  results[i].unit = flc_unit(c.random);
  results[i].triangle_random = flc_triangle_random(c.random, c.random * 3u, c.random * 7u, c.random * 11u, i);
}
)";

TEST(FlcSharedGpu, ComputeShaderAgreesWithTheHost) {
  gl::EglContext context("", false);
  const gl::Program program = gl::build_program({{GL_COMPUTE_SHADER, "flc_shared_gpu_test", kShader}});

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Case> cases(4096);
  for (Case& c : cases) {
    c.levels = static_cast<int>(rng() % 11);
    c.k = static_cast<int>(rng() % (c.levels + 1));
    c.s0 = std::exp2(unit(rng) * 20.0f - 10.0f);
    c.mu = 1.05f + unit(rng) * 6.0f;
    c.d0 = std::sqrt(c.s0) * (0.5f + 4.0f * unit(rng));
    c.d = c.d0 * std::exp2(unit(rng) * 24.0f - 8.0f);
    c.inverse_cumulative_n = flc::flc_inverse_cumulative_area(c.s0, c.mu, c.levels);
    c.area = unit(rng) * 1.5f / c.inverse_cumulative_n;
    c.u = unit(rng);
    c.u1 = unit(rng);
    c.u2 = unit(rng);
    c.random = static_cast<uint32_t>(rng());
  }
  const gl::Buffer case_buffer = gl::make_buffer(cases.size() * sizeof(Case), cases.data(), 0);
  const gl::Buffer result_buffer = gl::make_buffer(cases.size() * sizeof(Result), nullptr, 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, case_buffer.id());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, result_buffer.id());
  glUseProgram(program.id());
  glDispatchCompute(static_cast<GLuint>(cases.size() / 64), 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<Result> gpu(cases.size());
  glGetNamedBufferSubData(result_buffer.id(), 0, static_cast<GLsizeiptr>(gpu.size() * sizeof(Result)), gpu.data());
  ASSERT_EQ(glGetError(), static_cast<GLenum>(GL_NO_ERROR));

  int level_checks = 0;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Case& c = cases[i];
    const Result& r = gpu[i];
    const auto close = [](float a, float b) { return std::abs(a - b) <= 1e-5f * std::max(1.0f, std::abs(b)); };
    // A u within float rounding of a level threshold may fall either side on either processor.
    bool near_threshold = false;
    for (int k = 0; k <= c.levels; ++k)
      near_threshold |= std::abs(c.u - c.area * flc::flc_inverse_cumulative_area(c.s0, c.mu, k)) < 1e-5f;
    if (!near_threshold) {
      EXPECT_EQ(static_cast<int>(r.level), flc::flc_level(c.u, c.area, c.s0, c.mu, c.levels)) << i;
      ++level_checks;
    }
    EXPECT_TRUE(close(r.partition_value, flc::flc_partition(c.d, c.k, c.levels, c.d0, c.mu))) << i;
    EXPECT_TRUE(close(r.inverse_cumulative, c.inverse_cumulative_n)) << i;
    EXPECT_TRUE(close(r.support, flc::flc_support_distance(c.k, c.levels, c.d0, c.mu))) << i;
    const glm::vec3 point = flc::flc_triangle_point(c.u1, c.u2);
    for (int j = 0; j < 3; ++j) EXPECT_TRUE(close(r.point[j], point[j])) << i;
    EXPECT_TRUE(close(r.oversize_weight, flc::flc_oversize_weight(c.area, c.inverse_cumulative_n))) << i;
    EXPECT_EQ(r.unit, flc::flc_unit(c.random)) << i;
    EXPECT_EQ(r.triangle_random, flc::flc_triangle_random(c.random, c.random * 3u, c.random * 7u, c.random * 11u,
                                                          static_cast<uint32_t>(i)))
        << i;
  }
  EXPECT_GT(level_checks, 4000);
}

}  // namespace
}  // namespace bounce::test
