#include "passes/ray_checks/ray_checks.h"

#include <algorithm>
#include <bit>
#include <tuple>

#include "common/parallel.h"

namespace bounce {

namespace {

constexpr GLuint kBinding = 16;      // ray_checks.glsl's RayChecks
constexpr std::size_t kHeader = 16;  // the count, padded to the array's alignment
static_assert(sizeof(RayChecks::Pair) == 5 * 4 * sizeof(float));

}  // namespace

void RayChecks::bind(std::size_t pixels) {
  // A sample that asks for more than the buffer holds loses the rest of its checks (the rule's verdict stands for
  // them) and grows it for the next.
  const std::size_t wanted = std::max({wanted_, pixels, std::size_t(1024)});
  gl::reserve_buffer(buffer_, bytes_, kHeader + wanted * sizeof(Pair));
  const uint32_t zero = 0;
  glClearNamedBufferSubData(buffer_.id(), GL_R32UI, 0, sizeof zero, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kBinding, buffer_.id());
}

void RayChecks::correct(const RayCheckSettings& checks, GLuint image, GLuint also, int width, int height) {
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  uint32_t count = 0;
  glGetNamedBufferSubData(buffer_.id(), 0, sizeof count, &count);
  wanted_ = std::max(wanted_, std::size_t(count));
  pairs_.resize(std::min(std::size_t(count), (bytes_ - kHeader) / sizeof(Pair)));
  if (pairs_.empty()) return;
  glGetNamedBufferSubData(buffer_.id(), kHeader, GLsizeiptr(pairs_.size() * sizeof(Pair)), pairs_.data());
  // The GPU appends in no fixed order: sorted, the sums are the same for a seed.
  const auto key = [](const Pair& pair) {
    return std::tuple(pair.pixel, std::bit_cast<uint32_t>(pair.light_verdict.x),
                      std::bit_cast<uint32_t>(pair.light_verdict.y), std::bit_cast<uint32_t>(pair.light_verdict.z),
                      std::bit_cast<uint32_t>(pair.light_normal.w));
  };
  std::sort(pairs_.begin(), pairs_.end(), [key](const Pair& a, const Pair& b) { return key(a) < key(b); });
  const float offset = checks.scene.ray_offset();
  seen_.resize(pairs_.size());
  parallel_for(pairs_.size(), 0, 256, [&](std::size_t i) {
    const Pair& pair = pairs_[i];
    seen_[i] = checks.scene.clear_between(glm::vec3(pair.light_verdict) + glm::vec3(pair.light_normal) * offset,
                                          glm::vec3(pair.receiver) + glm::vec3(pair.receiver_normal) * offset)
                   ? 1.0f
                   : 0.0f;
  });
  const float weight = 1.0f / checks.share;
  add_to(image, width, height, weight, false);
  if (also != 0) add_to(also, width, height, weight, true);
  gl::check("Ray Checks");
}

void RayChecks::add_to(GLuint image, int width, int height, float weight, bool marked_only) {
  light_.resize(std::size_t(width) * std::size_t(height));
  glGetTextureImage(image, 0, GL_RGBA, GL_FLOAT, GLsizei(light_.size() * sizeof(glm::vec4)), light_.data());
  for (std::size_t i = 0; i < pairs_.size(); ++i) {
    const Pair& pair = pairs_[i];
    if (pair.pixel < light_.size() && (!marked_only || pair.light_normal.w != 0.0f))
      light_[pair.pixel] += glm::vec4(pair.unshadowed * (weight * (seen_[i] - pair.light_verdict.w)), 0.0f);
  }
  glTextureSubImage2D(image, 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, light_.data());
}

}  // namespace bounce
