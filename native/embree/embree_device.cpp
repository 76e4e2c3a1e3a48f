#include "embree_device.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

#include <glm/geometric.hpp>

#include "common/fault_injection.h"

// CMake names the major version it linked (BOUNCE_EMBREE_VERSION_MAJOR); the headers must be the same ones.
#if defined(BOUNCE_EMBREE_VERSION_MAJOR) ? BOUNCE_EMBREE_VERSION_MAJOR == 4 : __has_include(<embree4/rtcore.h>)
#include <embree4/rtcore.h>
#define BOUNCE_EMBREE4 1
#else
#include <embree3/rtcore.h>
#define BOUNCE_EMBREE4 0
#endif

#ifdef RTC_NAMESPACE_USE
RTC_NAMESPACE_USE
#endif

namespace bounce::embree {

struct Device::Impl {
  RTCDevice device = nullptr;
  std::mutex mutex;
  std::string last_error;  // the latest message of the error callback

  static void on_error(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->mutex);
    self->last_error = "Embree error " + std::to_string(int(code)) + ": " + (message ? message : "");
  }

  // Throws when Embree reported an error since the last check.
  void check(const char* what) {
    const RTCError code = rtcGetDeviceError(device);
    if (code == RTC_ERROR_NONE) return;
    std::lock_guard lock(mutex);
    throw std::runtime_error(std::string(what) + ": " +
                             (last_error.empty() ? "Embree error " + std::to_string(int(code)) : last_error));
  }
};

Device::Device() : impl_(std::make_unique<Impl>()) {
  if (fault_injected("embree")) throw std::runtime_error("rtcNewDevice failed: injected by BOUNCE_INJECT_FAULT");
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) {
    throw std::runtime_error("rtcNewDevice failed: Embree error " + std::to_string(int(rtcGetDeviceError(nullptr))));
  }
  rtcSetDeviceErrorFunction(impl_->device, &Impl::on_error, impl_.get());
}

Device::~Device() { rtcReleaseDevice(impl_->device); }

const char* Device::version() { return RTC_VERSION_STRING; }

namespace {

struct Geometry {
  std::vector<glm::vec3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// Embree's ray.valid(): finite values below its 1.844e18 limit, 0 <= tnear <= tfar (debug builds assert on it,
// and Debian's keep assertions, so an invalid ray would abort the process).
bool valid_ray(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) {
  constexpr float kLimit = 1.8e18f;
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(origin[c]) < kLimit) || !(std::abs(dir[c]) < kLimit)) return false;
  return tmin >= 0.0f && !(tmin > tmax) && !std::isnan(tmax);
}

void init_ray(RTCRay& ray, glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) {
  ray.org_x = origin.x;
  ray.org_y = origin.y;
  ray.org_z = origin.z;
  ray.tnear = tmin;
  ray.dir_x = dir.x;
  ray.dir_y = dir.y;
  ray.dir_z = dir.z;
  ray.time = 0.0f;
  ray.tfar = tmax;
  ray.mask = 0xFFFFFFFFu;
  ray.id = 0;
  ray.flags = 0;
}

}  // namespace

struct Scene::Impl {
  std::shared_ptr<Device> device;
  RTCScene scene = nullptr;
  std::vector<Geometry> geometries;
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};
  bool committed = false;

  void require_committed() const {
    if (!committed) throw std::logic_error("bounce::embree::Scene: query before commit()");
  }
};

Scene::Scene(std::shared_ptr<Device> device) : impl_(std::make_unique<Impl>()) {
  impl_->device = device ? std::move(device) : std::make_shared<Device>();
  impl_->scene = rtcNewScene(impl_->device->impl_->device);
  impl_->device->impl_->check("rtcNewScene");
}

Scene::~Scene() {
  if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
}

Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&& other) noexcept {
  if (this != &other) {
    if (impl_ && impl_->scene) rtcReleaseScene(impl_->scene);
    impl_ = std::move(other.impl_);
  }
  return *this;
}

uint32_t Scene::add_triangles(std::span<const glm::vec3> positions,
                              std::span<const std::array<uint32_t, 3>> triangles) {
  if (impl_->committed) throw std::logic_error("bounce::embree::Scene: add_triangles after commit()");
  for (const auto& triangle : triangles) {
    for (uint32_t index : triangle) {
      if (index >= positions.size()) throw std::out_of_range("bounce::embree::Scene: vertex index out of range");
    }
  }
  const auto id = static_cast<uint32_t>(impl_->geometries.size());
  Geometry& geometry = impl_->geometries.emplace_back();
  geometry.positions.assign(positions.begin(), positions.end());
  geometry.triangles.assign(triangles.begin(), triangles.end());
  for (const glm::vec3& p : positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    impl_->lo = glm::min(impl_->lo, p);
    impl_->hi = glm::max(impl_->hi, p);
  }
  // Embree rejects empty buffers; an empty geometry keeps its id and simply has nothing to hit.
  if (triangles.empty() || positions.empty()) return id;

  RTCDevice device = impl_->device->impl_->device;
  RTCGeometry handle = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(handle, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                               3 * sizeof(float), positions.size()));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(handle, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), triangles.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(handle);
    impl_->device->impl_->check("rtcSetNewGeometryBuffer");
    throw std::runtime_error("rtcSetNewGeometryBuffer failed");
  }
  for (std::size_t i = 0; i < positions.size(); ++i) {
    vertices[3 * i + 0] = positions[i].x;
    vertices[3 * i + 1] = positions[i].y;
    vertices[3 * i + 2] = positions[i].z;
  }
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    for (int k = 0; k < 3; ++k) indices[3 * i + k] = triangles[i][k];
  }
  rtcCommitGeometry(handle);
  rtcAttachGeometryByID(impl_->scene, handle, id);
  rtcReleaseGeometry(handle);
  impl_->device->impl_->check("add_triangles");
  return id;
}

uint32_t Scene::add_triangles(std::span<const glm::vec3> soup) {
  std::vector<std::array<uint32_t, 3>> triangles(soup.size() / 3);
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const auto base = static_cast<uint32_t>(3 * i);
    triangles[i] = {base, base + 1, base + 2};
  }
  return add_triangles(soup.first(3 * triangles.size()), triangles);
}

void Scene::commit() {
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcCommitScene(impl_->scene);
  impl_->device->impl_->check("rtcCommitScene");
  impl_->committed = true;
}

bool Scene::committed() const { return impl_->committed; }

std::optional<Hit> Scene::intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const {
  impl_->require_committed();
  if (!valid_ray(origin, dir, tmin, tmax)) return std::nullopt;
  RTCRayHit query{};
  init_ray(query.ray, origin, dir, tmin, tmax);
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.primID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if BOUNCE_EMBREE4
  rtcIntersect1(impl_->scene, &query);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(impl_->scene, &context, &query);
#endif
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  Hit hit;
  hit.t = query.ray.tfar;
  hit.geometry_id = query.hit.geomID;
  hit.prim_id = query.hit.primID;
  hit.u = query.hit.u;
  hit.v = query.hit.v;
  const auto p = triangle(hit.geometry_id, hit.prim_id);
  const glm::vec3 cross = glm::cross(p[1] - p[0], p[2] - p[0]);
  const float length = glm::length(cross);
  // A sliver that float32 flattens (a corner 1e9 m out, the others a metre apart) has no normal of its own, and
  // normalizing its zero cross product gave NaN: it faces the ray.
  hit.normal = length > 0.0f && std::isfinite(length) ? cross / length : -glm::normalize(dir);
  return hit;
}

bool Scene::occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax) const {
  impl_->require_committed();
  if (!valid_ray(origin, dir, tmin, tmax)) return false;
  RTCRay query{};
  init_ray(query, origin, dir, tmin, tmax);
#if BOUNCE_EMBREE4
  rtcOccluded1(impl_->scene, &query);
#else
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcOccluded1(impl_->scene, &context, &query);
#endif
  // Embree marks an occluded ray by setting tfar to -inf.
  return query.tfar < 0.0f && std::isinf(query.tfar);
}

std::optional<Hit> Scene::intersect(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax,
                                    const HitFilter& counts) const {
  constexpr int kMaxSkipped = 256;  // cut-outs passed through before the ray counts as blocked
  for (int skipped = 0; skipped < kMaxSkipped; ++skipped) {
    std::optional<Hit> hit = intersect(origin, dir, tmin, tmax);
    if (!hit || !counts || counts(*hit)) return hit;
    // Past this hit: the next float up, and a relative step so a hit far along the ray is not found again.
    tmin = std::max(std::nextafter(hit->t, std::numeric_limits<float>::infinity()), hit->t * (1.0f + 1e-6f));
  }
  return intersect(origin, dir, tmin, tmax);
}

bool Scene::occluded(glm::vec3 origin, glm::vec3 dir, float tmin, float tmax, const HitFilter& counts) const {
  if (!counts) return occluded(origin, dir, tmin, tmax);
  return intersect(origin, dir, tmin, tmax, counts).has_value();
}

std::array<glm::vec3, 3> Scene::triangle(uint32_t geometry_id, uint32_t prim_id) const {
  const Geometry& geometry = impl_->geometries.at(geometry_id);
  const auto& indices = geometry.triangles.at(prim_id);
  return {geometry.positions[indices[0]], geometry.positions[indices[1]], geometry.positions[indices[2]]};
}

uint32_t Scene::geometry_count() const { return static_cast<uint32_t>(impl_->geometries.size()); }

uint32_t Scene::triangle_count(uint32_t geometry_id) const {
  return static_cast<uint32_t>(impl_->geometries.at(geometry_id).triangles.size());
}

glm::vec3 Scene::bounds_min() const { return impl_->lo; }
glm::vec3 Scene::bounds_max() const { return impl_->hi; }

}  // namespace bounce::embree
