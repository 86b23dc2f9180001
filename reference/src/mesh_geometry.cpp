// Triangle meshes through Embree 3: a trusted ray tracer that shares no code
// with the voxelizer's distance field or the octree.
#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <limits>
#include <stdexcept>
#include <string>

#include "svo/reference/geometry.h"

namespace svo::reference {

namespace {

[[noreturn]] void fail(RTCDevice device, const std::string& what) {
  RTCError code = rtcGetDeviceError(device);
  throw std::runtime_error("Embree: " + what + " failed (error " + std::to_string(int(code)) + ")");
}

class MeshGeometry : public Geometry {
 public:
  explicit MeshGeometry(voxelizer::TriangleMesh mesh) : mesh_(std::move(mesh)) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) fail(nullptr, "creating the device");
    scene_ = rtcNewScene(device_);
    if (!scene_) fail(device_, "creating the scene");
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geometry) fail(device_, "creating the triangle geometry");
    // Vertices relative to the bounds' centre, so that float keeps the most precision.
    const voxelizer::Box& b = mesh_.bounds;
    centre_ = 0.5 * (glm::dvec3(b.lo) + glm::dvec3(b.hi));
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 3 * sizeof(float), mesh_.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                   3 * sizeof(unsigned), mesh_.triangles.size()));
    if (!vertices || !indices) fail(device_, "allocating the mesh buffers");
    for (size_t i = 0; i < mesh_.positions.size(); ++i) {
      glm::dvec3 p = mesh_.positions[i] - centre_;
      vertices[3 * i] = float(p.x), vertices[3 * i + 1] = float(p.y), vertices[3 * i + 2] = float(p.z);
    }
    for (size_t i = 0; i < mesh_.triangles.size(); ++i) {
      const glm::ivec3& t = mesh_.triangles[i];
      indices[3 * i] = unsigned(t.x), indices[3 * i + 1] = unsigned(t.y), indices[3 * i + 2] = unsigned(t.z);
    }
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) fail(device_, "building the BVH");
    glm::dvec3 e = glm::dvec3(b.hi) - glm::dvec3(b.lo);
    offset_ = 1e-5 * std::max({e.x, e.y, e.z});
  }

  ~MeshGeometry() override {
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
  }
  MeshGeometry(const MeshGeometry&) = delete;
  MeshGeometry& operator=(const MeshGeometry&) = delete;

  std::optional<SurfaceHit> intersect(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit rh{};
    set_ray(rh.ray, o, d, t_min, t_max);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID || rh.hit.primID >= mesh_.triangles.size()) return std::nullopt;
    const size_t tri = rh.hit.primID;
    // Embree's (u, v) weigh the second and third vertex.
    const glm::dvec3 bary(1.0 - double(rh.hit.u) - double(rh.hit.v), rh.hit.u, rh.hit.v);
    const glm::ivec3& t = mesh_.triangles[tri];
    SurfaceHit hit;
    hit.t = rh.ray.tfar;
    hit.position = bary.x * mesh_.positions[size_t(t.x)] + bary.y * mesh_.positions[size_t(t.y)] +
                   bary.z * mesh_.positions[size_t(t.z)];
    hit.normal = mesh_.face_normals[tri];
    if (glm::dot(glm::dvec3(hit.normal), d) > 0) hit.normal = -hit.normal;
    hit.colour = mesh_.colour(tri, bary);
    hit.material = mesh_.face_material.empty() ? 0u : mesh_.face_material[tri];
    return hit;
  }

  bool occluded(glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const override {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay ray{};
    set_ray(ray, o, d, t_min, t_max);
    rtcOccluded1(scene_, &context, &ray);
    return ray.tfar == -std::numeric_limits<float>::infinity();
  }

  float sigma_rho2() const override { return mesh_.sigma_rho2; }
  voxelizer::Box bounds() const override { return mesh_.bounds; }
  std::vector<std::string> materials() const override { return mesh_.materials; }
  double shadow_offset() const override { return offset_; }

 private:
  void set_ray(RTCRay& ray, glm::dvec3 o, glm::dvec3 d, double t_min, double t_max) const {
    const glm::dvec3 local = o - centre_;
    ray.org_x = float(local.x), ray.org_y = float(local.y), ray.org_z = float(local.z);
    ray.dir_x = float(d.x), ray.dir_y = float(d.y), ray.dir_z = float(d.z);
    ray.tnear = float(t_min);
    ray.tfar =
        t_max < double(std::numeric_limits<float>::max()) ? float(t_max) : std::numeric_limits<float>::infinity();
    ray.mask = ~0u;
    ray.flags = 0;
    ray.time = 0;
  }

  voxelizer::TriangleMesh mesh_;
  glm::dvec3 centre_{0};
  double offset_ = 1e-5;
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

}  // namespace

std::unique_ptr<Geometry> mesh_geometry(voxelizer::TriangleMesh mesh) {
  return std::make_unique<MeshGeometry>(std::move(mesh));
}

}  // namespace svo::reference
