#pragma once
// The object as a rigid body: its collision pieces, its density and the
// mass properties of the solid its closed mesh bounds.

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"

namespace hfts::physics {

/// A convex piece of the object's collision shape, in the object frame.
struct ConvexPiece {
  db::Points3 vertices;
  db::Faces3 faces;  ///< outward winding
};

/// What the object collides as: its convex decomposition
/// (ObjectGeometry::convex_parts, every database hfts-preprocess writes has
/// one), else its convex hull (hull_vertices / hull_faces).
std::vector<ConvexPiece> collisionPieces(const db::ObjectDatabase& object);

/// "hull" or "convex_parts": which shape collisionPieces() returns.
std::string collisionShapeName(const db::ObjectDatabase& object);

/// Volume, centre of mass and inertia of a uniform solid.
struct MassProperties {
  double volume = 0.0;  ///< m^3
  double mass = 0.0;    ///< kg
  Eigen::Vector3d center_of_mass = Eigen::Vector3d::Zero();
  /// About the centre of mass, in the mesh's frame (kg m^2).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

/// The mass properties of the solid a closed, outward-wound triangle mesh
/// bounds, at `density` (kg/m^3), by signed tetrahedra from the origin
/// (each face with the origin; exact for any closed mesh). Throws
/// InvalidArgument ("density", "faces") for a density that is not > 0,
/// faces indexing past the vertices, or a mesh whose signed volume is not
/// positive (open, inside out or flat).
MassProperties solidMassProperties(const db::Points3& vertices, const db::Faces3& faces,
                                   double density);

/// The object's solid: its mesh when the database says it is closed, else
/// the union of its convex parts (an open mesh bounds no volume), else its
/// convex hull.
MassProperties objectMassProperties(const db::ObjectDatabase& object, double density);

/// The one place where the object's density is chosen: `requested` (the
/// options') when set, else the object's own (db::ObjectDatabase::density,
/// db::kDefaultDensity unless its build or sidecar said otherwise).
double objectDensity(const db::ObjectDatabase& object, const std::optional<double>& requested);

}  // namespace hfts::physics
