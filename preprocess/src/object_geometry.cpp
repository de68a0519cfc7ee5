#include "preprocess/object_geometry.h"

#include "preprocess/convex_decomposition.h"

namespace hfts::preprocess {

db::ObjectGeometry objectGeometry(const TriangleMesh& mesh, bool closed, const ConvexHull& hull,
                                  const CenterOfMass& com) {
  db::ObjectGeometry g;
  g.hull_vertices = hull.vertices();
  g.hull_faces = hull.faces();
  g.mesh_vertices = mesh.vertices;
  g.mesh_triangles = mesh.triangles;
  g.closed = closed;
  // The centroid counts an overlap of closed parts twice (a small shift
  // for the bundled objects); the volume counts it once.
  g.center_of_mass = com.point;
  g.volume = closed ? solidVolume(mesh) : com.volume;
  g.center_of_mass_method = com.method;
  // The farthest surface point from any point is a hull vertex.
  g.rho = (hull.vertices().rowwise() - g.center_of_mass.transpose()).rowwise().norm().maxCoeff();
  g.bbox_min = mesh.vertices.colwise().minCoeff().transpose();
  g.bbox_max = mesh.vertices.colwise().maxCoeff().transpose();
  return g;
}

}  // namespace hfts::preprocess
