#include "splat/raytrace/ray_tracer.hpp"

#include <limits>
#include <string>

#include <embree3/rtcore.h>

#include "splat/core/error.hpp"

namespace splat::raytrace {
namespace {

// Embree reports asynchronous failures through this callback; turning them into an exception
// at the next check keeps error handling in one style.
void remember_error(void* user, RTCError code, const char* message) {
  if (code != RTC_ERROR_NONE) *static_cast<std::string*>(user) = message ? message : "unknown";
}

}  // namespace

struct RayTracer::Impl {
  std::string error;
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
  void check(const char* step) const {
    if (!error.empty()) throw Error(std::string("Embree: ") + step + ": " + error);
  }
};

RayTracer::RayTracer(const Mesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw Error("Embree: cannot create a device");
  rtcSetDeviceErrorFunction(impl_->device, remember_error, &impl_->error);
  impl_->scene = rtcNewScene(impl_->device);
  // Robust traversal: no missed hits along shared edges, which would show as speckles.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
      mesh.positions.size()));
  std::uint32_t* indices = static_cast<std::uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(std::uint32_t),
      mesh.triangle_count()));
  impl_->check("allocating buffers");
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    for (int c = 0; c < 3; ++c) vertices[3 * v + c] = mesh.positions[v][c];
  for (std::size_t i = 0; i < mesh.indices.size(); ++i) indices[i] = mesh.indices[i];
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);  // the scene holds its own reference
  rtcCommitScene(impl_->scene);
  impl_->check("building the scene");
}

RayTracer::~RayTracer() = default;

bool RayTracer::intersect(const glm::vec3& origin, const glm::vec3& direction, RayHit& hit,
                          float t_near, float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = origin.x; rh.ray.org_y = origin.y; rh.ray.org_z = origin.z;
  rh.ray.dir_x = direction.x; rh.ray.dir_y = direction.y; rh.ray.dir_z = direction.z;
  rh.ray.tnear = t_near;
  rh.ray.tfar = t_far;
  rh.ray.mask = std::numeric_limits<unsigned>::max();
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  hit.t = rh.ray.tfar;
  hit.triangle = rh.hit.primID;
  hit.u = rh.hit.u;
  hit.v = rh.hit.v;
  return true;
}

bool RayTracer::occluded(const glm::vec3& origin, const glm::vec3& direction, float t_near,
                         float t_far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = origin.x; ray.org_y = origin.y; ray.org_z = origin.z;
  ray.dir_x = direction.x; ray.dir_y = direction.y; ray.dir_z = direction.z;
  ray.tnear = t_near;
  ray.tfar = t_far;
  ray.mask = std::numeric_limits<unsigned>::max();
  rtcOccluded1(impl_->scene, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

}  // namespace splat::raytrace
