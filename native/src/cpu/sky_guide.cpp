#include "cpu/sky_guide.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <span>

#include "sampling.h"

namespace bounce::cpu {
namespace {

// The density per steradian of a direction in bin b of a box's cumulative sums (learned: sums[kBins] > 0).
float bin_pdf(const double* sums, std::size_t b) {
  return float((sums[b + 1] - sums[b]) / sums[SkyGuide::kBins]) / sphere_bins::kSolidAngle;
}

}  // namespace

SkyGuide::SkyGuide(glm::vec3 lo, glm::vec3 hi) : grid_(lo, hi, kCellsPerSide) {
  learned_.assign(2 * grid_.size() * kBins, 0);
  cdf_.assign(2 * grid_.size() * (kBins + 1), 0.0);
}

void SkyGuide::learn(uint32_t side, glm::vec3 x, glm::vec3 w, float share) {
  const std::size_t cell = grid_.index_of(x);
  if (cell >= grid_.size() || !(share > 0.0f) || !std::isfinite(w.x + w.y + w.z)) return;
  const auto units = uint64_t(double(std::min(share, 1.0f)) * 0x1p32);
  const std::size_t at = ((side & 1u) * grid_.size() + cell) * kBins + std::size_t(sphere_bins::of(w));
  std::atomic_ref<uint64_t>(learned_[at]).fetch_add(units, std::memory_order_relaxed);
}

void SkyGuide::update() {
  for (std::size_t box = 0; box < 2 * grid_.size(); ++box) {
    double* sums = &cdf_[box * (kBins + 1)];
    sums[0] = 0.0;
    for (int b = 0; b < kBins; ++b) sums[b + 1] = sums[b] + double(learned_[box * kBins + std::size_t(b)]);
  }
}

const double* SkyGuide::cdf(uint32_t side, glm::vec3 x) const {
  const std::size_t cell = grid_.index_of(x);
  if (cell >= grid_.size()) return nullptr;
  return &cdf_[((1u - (side & 1u)) * grid_.size() + cell) * (kBins + 1)];
}

bool SkyGuide::guides(uint32_t side, glm::vec3 x) const {
  const double* sums = cdf(side, x);
  return sums && sums[kBins] > 0.0;
}

float SkyGuide::pdf(uint32_t side, glm::vec3 x, glm::vec3 w) const {
  const double* sums = cdf(side, x);
  if (!sums || !(sums[kBins] > 0.0)) return 0.0f;
  return bin_pdf(sums, std::size_t(sphere_bins::of(w)));
}

std::optional<SkyGuide::Draw> SkyGuide::draw(uint32_t side, glm::vec3 x, float pick, glm::vec2 within) const {
  const double* sums = cdf(side, x);
  if (!sums || !(sums[kBins] > 0.0)) return std::nullopt;
  const std::size_t b = find_in_cdf(std::span<const double>(sums, kBins + 1), double(pick) * sums[kBins]);
  return Draw{sphere_bins::direction(int(b), within), bin_pdf(sums, b)};
}

}  // namespace bounce::cpu
