#include "hfts_db/triangle_bvh.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hfts::db {

struct TriangleBvh::Impl {
  TriangleMesh mesh;
  double extent = 0.0;  ///< largest absolute vertex coordinate
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  ~Impl() {
    if (scene != nullptr) rtcReleaseScene(scene);
    if (device != nullptr) rtcReleaseDevice(device);
  }
};

namespace {

void attachTriangles(RTCDevice device, RTCScene scene, const TriangleMesh& mesh) {
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), static_cast<std::size_t>(mesh.vertices.rows())));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
      static_cast<std::size_t>(mesh.triangles.rows())));
  if (vertices == nullptr || indices == nullptr) {
    rtcReleaseGeometry(geometry);
    throw std::runtime_error("Embree: cannot allocate geometry buffers");
  }
  for (Eigen::Index i = 0; i < mesh.vertices.size(); ++i)
    vertices[i] = static_cast<float>(mesh.vertices.data()[i]);
  std::copy(mesh.triangles.data(), mesh.triangles.data() + mesh.triangles.size(), indices);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene, geometry);
  rtcReleaseGeometry(geometry);
}

struct NearQuery {
  const TriangleMesh* mesh;
  Eigen::Vector3d point;
  bool found = false;
};

/// Embree calls this for every triangle whose bounds meet the query
/// sphere; the exact distance decides.
bool nearCallback(RTCPointQueryFunctionArguments* args) {
  auto* query = static_cast<NearQuery*>(args->userPtr);
  const unsigned f = args->primID;
  const TriangleMesh& mesh = *query->mesh;
  auto corner = [&](int k) -> Eigen::Vector3d { return mesh.vertices.row(mesh.triangles(f, k)); };
  const Eigen::Vector3d q = closestPointOnTriangle(query->point, corner(0), corner(1), corner(2));
  if ((q - query->point).norm() > static_cast<double>(args->query->radius)) return false;
  query->found = true;
  args->query->radius = 0.0f;  // answered: shrink the sphere so traversal ends
  return true;
}

Eigen::Vector3d closestOnTriangle(const TriangleMesh& mesh, std::uint32_t f,
                                  const Eigen::Vector3d& p) {
  auto corner = [&](int k) -> Eigen::Vector3d { return mesh.vertices.row(mesh.triangles(f, k)); };
  return closestPointOnTriangle(p, corner(0), corner(1), corner(2));
}

struct NearestQuery {
  const TriangleMesh* mesh;
  Eigen::Vector3d point;
  double slack;  ///< bound on Embree's single-precision error in culling
  ClosestPoint best;
};

/// Embree culls in single precision (float vertices, float query point):
/// the radius it is given exceeds the best double distance by `slack`, so
/// the truly nearest triangle is never culled.
float cullingRadius(double distance, double slack) {
  const float radius = static_cast<float>(distance + slack);
  return std::nextafter(radius, std::numeric_limits<float>::infinity());
}

bool nearestCallback(RTCPointQueryFunctionArguments* args) {
  auto* query = static_cast<NearestQuery*>(args->userPtr);
  const Eigen::Vector3d q = closestOnTriangle(*query->mesh, args->primID, query->point);
  const double d = (q - query->point).norm();
  if (!(d < query->best.distance)) return false;
  query->best = {q, d, args->primID};
  args->query->radius = cullingRadius(d, query->slack);
  return true;
}

}  // namespace

TriangleBvh::TriangleBvh(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  impl_->mesh = mesh;
  impl_->extent = mesh.vertices.size() > 0 ? mesh.vertices.cwiseAbs().maxCoeff() : 0.0;
  // One thread per BVH: the batch tool parallelises over objects.
  impl_->device = rtcNewDevice("threads=1");
  if (impl_->device == nullptr) throw std::runtime_error("Embree: cannot create a device");
  impl_->scene = rtcNewScene(impl_->device);
  if (mesh.triangles.rows() > 0) attachTriangles(impl_->device, impl_->scene, mesh);
  rtcCommitScene(impl_->scene);
  if (rtcGetDeviceError(impl_->device) != RTC_ERROR_NONE)
    throw std::runtime_error("Embree: building the BVH failed");
}

TriangleBvh::~TriangleBvh() = default;

bool TriangleBvh::escapes(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = static_cast<float>(origin.x());
  ray.org_y = static_cast<float>(origin.y());
  ray.org_z = static_cast<float>(origin.z());
  ray.dir_x = static_cast<float>(direction.x());
  ray.dir_y = static_cast<float>(direction.y());
  ray.dir_z = static_cast<float>(direction.z());
  ray.tnear = 0.0f;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.mask = 0xffffffffu;
  rtcOccluded1(impl_->scene, &context, &ray);
  return ray.tfar >= 0.0f;  // Embree sets tfar to -inf on a hit
}

std::optional<RayHit> TriangleBvh::firstHit(const Eigen::Vector3d& origin,
                                            const Eigen::Vector3d& direction) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query{};
  query.ray.org_x = static_cast<float>(origin.x());
  query.ray.org_y = static_cast<float>(origin.y());
  query.ray.org_z = static_cast<float>(origin.z());
  query.ray.dir_x = static_cast<float>(direction.x());
  query.ray.dir_y = static_cast<float>(direction.y());
  query.ray.dir_z = static_cast<float>(direction.z());
  query.ray.tnear = 0.0f;
  query.ray.tfar = std::numeric_limits<float>::infinity();
  query.ray.mask = 0xffffffffu;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return RayHit{static_cast<double>(query.ray.tfar), query.hit.primID};
}

bool TriangleBvh::isWithin(const Eigen::Vector3d& point, double radius) const {
  RTCPointQuery query{};
  query.x = static_cast<float>(point.x());
  query.y = static_cast<float>(point.y());
  query.z = static_cast<float>(point.z());
  query.radius = static_cast<float>(radius);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  NearQuery data{&impl_->mesh, point};
  rtcPointQuery(impl_->scene, &query, &context, nearCallback, &data);
  return data.found;
}

ClosestPoint TriangleBvh::closestPoint(const Eigen::Vector3d& point, std::uint32_t hint) const {
  const TriangleMesh& mesh = impl_->mesh;
  // 1e-6 is 16 units in the last place of a float: the rounding of the
  // vertices, of the query point and of Embree's box test together.
  const double slack = 1e-6 * (impl_->extent + point.cwiseAbs().maxCoeff());
  NearestQuery data{&mesh, point, slack, {}};
  data.best.distance = std::numeric_limits<double>::infinity();
  if (mesh.triangles.rows() == 0) return data.best;
  if (static_cast<Eigen::Index>(hint) >= mesh.triangles.rows()) hint = 0;
  data.best.point = closestOnTriangle(mesh, hint, point);
  data.best.distance = (data.best.point - point).norm();
  data.best.triangle = hint;
  RTCPointQuery query{};
  query.x = static_cast<float>(point.x());
  query.y = static_cast<float>(point.y());
  query.z = static_cast<float>(point.z());
  query.radius = cullingRadius(data.best.distance, slack);
  RTCPointQueryContext context;
  rtcInitPointQueryContext(&context);
  rtcPointQuery(impl_->scene, &query, &context, nearestCallback, &data);
  return data.best;
}

Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi-region walk (Ericson, Real-Time Collision Detection, 5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace hfts::db
