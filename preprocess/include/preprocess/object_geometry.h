#pragma once
// An object database's geometry from its mesh (the builder's last step
// before the contacts): mesh, hull, centre of mass and volume, rho and
// bounding box.

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"
#include "preprocess/center_of_mass.h"
#include "preprocess/convex_hull.h"

namespace hfts::preprocess {

/// Hull, centre of mass and volume (`com`, from centerOfMass in
/// center_of_mass.h), rho (largest distance from the centre of mass to the
/// surface) and bounding box. `closed` is the mesh's topology.
db::ObjectGeometry objectGeometry(const TriangleMesh& mesh, bool closed, const ConvexHull& hull,
                                  const CenterOfMass& com);

}  // namespace hfts::preprocess
