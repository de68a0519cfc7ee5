// The object's collision pieces, density and solid mass properties.
#include "physics/object_body.h"

#include <Eigen/Geometry>

#include <cmath>
#include <string>

#include "core/invalid_argument.h"

namespace hfts::physics {
namespace {

// The convex decomposition when the database has one (every database
// hfts-preprocess writes does); the hull otherwise (a database built in
// memory without one).
bool usesConvexParts(const db::ObjectDatabase& object) {
  return !object.geometry.convex_parts.empty();
}

void checkFaces(const db::Points3& vertices, const db::Faces3& faces) {
  const auto count = static_cast<std::uint32_t>(vertices.rows());
  if (faces.rows() == 0) throw InvalidArgument("faces", "the mesh has no triangles");
  if ((faces.array() >= count).any())
    throw InvalidArgument("faces", "index a vertex past the " + std::to_string(count) + " given");
}

}  // namespace

std::vector<ConvexPiece> collisionPieces(const db::ObjectDatabase& object) {
  if (!usesConvexParts(object))
    return {ConvexPiece{object.geometry.hull_vertices, object.geometry.hull_faces}};
  std::vector<ConvexPiece> pieces;
  for (const db::ConvexPiece& part : object.geometry.convex_parts)
    pieces.push_back({part.vertices, part.faces});
  return pieces;
}

std::string collisionShapeName(const db::ObjectDatabase& object) {
  return usesConvexParts(object) ? "convex_parts" : "hull";
}

MassProperties solidMassProperties(const db::Points3& vertices, const db::Faces3& faces,
                                   double density) {
  if (!(density > 0.0) || !std::isfinite(density))
    throw InvalidArgument("density", "must be a finite number > 0 (kg/m^3)");
  checkFaces(vertices, faces);
  // Tetrahedra from a point near the mesh, not the frame's origin, so that
  // large coordinates do not cancel.
  const Eigen::Vector3d reference = vertices.colwise().mean().transpose();
  double volume = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // integral of x x^T about `reference`
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)).transpose() - reference;
    const Eigen::Vector3d b = vertices.row(faces(f, 1)).transpose() - reference;
    const Eigen::Vector3d c = vertices.row(faces(f, 2)).transpose() - reference;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Eigen::Vector3d sum = a + b + c;
    volume += v;
    moment += v * sum / 4.0;
    second += v / 20.0 *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (!(volume > 0.0))
    throw InvalidArgument("faces", "the mesh bounds no positive volume (open, inside out or flat)");
  MassProperties out;
  out.volume = volume;
  out.mass = density * volume;
  const Eigen::Vector3d center = moment / volume;
  out.center_of_mass = reference + center;
  const Eigen::Matrix3d central = second - volume * center * center.transpose();
  out.inertia = density * (central.trace() * Eigen::Matrix3d::Identity() - central);
  return out;
}

MassProperties objectMassProperties(const db::ObjectDatabase& object, double density) {
  const db::ObjectGeometry& g = object.geometry;
  if (g.closed) return solidMassProperties(g.mesh_vertices, g.mesh_triangles, density);
  if (g.convex_parts.empty()) return solidMassProperties(g.hull_vertices, g.hull_faces, density);
  // A mesh that is not closed (a scan) bounds no volume of its own: the
  // convex parts cover its solid (within the decomposition's tolerance).
  MassProperties sum;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  std::vector<MassProperties> parts;
  for (const db::ConvexPiece& part : g.convex_parts) {
    parts.push_back(solidMassProperties(part.vertices, part.faces, density));
    sum.volume += parts.back().volume;
    sum.mass += parts.back().mass;
    moment += parts.back().mass * parts.back().center_of_mass;
  }
  sum.center_of_mass = moment / sum.mass;
  for (const MassProperties& p : parts) {  // parallel axis theorem
    const Eigen::Vector3d r = p.center_of_mass - sum.center_of_mass;
    sum.inertia +=
        p.inertia + p.mass * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
  }
  return sum;
}

double objectDensity(const db::ObjectDatabase& object, const std::optional<double>& requested) {
  return requested ? *requested : object.density;
}

}  // namespace hfts::physics
