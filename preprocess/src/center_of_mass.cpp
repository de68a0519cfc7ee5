#include "preprocess/center_of_mass.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <map>
#include <numeric>
#include <sstream>
#include <vector>

namespace hfts::preprocess {
namespace {

/// An undirected edge (a < b) and how often it is used a -> b minus how
/// often b -> a: the boundary chain's multiplicity on it.
struct ChainEdge {
  std::uint32_t a = 0, b = 0;
  int net = 0;
};

std::vector<ChainEdge> boundaryChain(const Triangles& triangles) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> net;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t from = triangles(t, k), to = triangles(t, (k + 1) % 3);
      if (from == to) continue;  // an edge of a collapsed triangle bounds nothing
      if (from < to)
        ++net[{from, to}];
      else
        --net[{to, from}];
    }
  std::vector<ChainEdge> chain;
  for (const auto& [edge, count] : net)
    if (count != 0) chain.push_back({edge.first, edge.second, count});
  return chain;
}

/// Union-find root with path halving.
std::uint32_t root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

double area(const Vertices& v, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  return 0.5 * (v.row(b) - v.row(a)).cross(v.row(c) - v.row(a)).norm();
}

/// The mean of some vertices and how far the farthest lies from their
/// least-squares plane.
struct PlaneFit {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double thickness = 0.0;
};

PlaneFit fitPlane(const Vertices& v, const std::vector<std::uint32_t>& indices) {
  PlaneFit fit;
  for (const std::uint32_t i : indices) fit.centre += v.row(i).transpose();
  fit.centre /= static_cast<double>(indices.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const std::uint32_t i : indices) {
    const Eigen::Vector3d d = v.row(i).transpose() - fit.centre;
    covariance += d * d.transpose();
  }
  const Eigen::Vector3d normal =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvectors().col(0);
  for (const std::uint32_t i : indices)
    fit.thickness =
        std::max(fit.thickness, std::abs(normal.dot(v.row(i).transpose() - fit.centre)));
  return fit;
}

/// A capped solid smaller than this fraction of its hull is a sheet, not a
/// body (a 10 cm cup of 0.1 mm foil still fills 5 thousandths of its hull).
constexpr double kMinVolumeOfHull = 1e-3;

}  // namespace

TriangleMesh withCaps(const TriangleMesh& mesh, const TriangleMesh& caps) {
  TriangleMesh out;
  out.vertices = caps.vertices;  // the mesh's vertices come first
  out.triangles.resize(mesh.triangles.rows() + caps.triangles.rows(), 3);
  out.triangles << mesh.triangles, caps.triangles;
  return out;
}

BoundaryCaps boundaryCaps(const TriangleMesh& mesh) {
  const std::vector<ChainEdge> chain = boundaryChain(mesh.triangles);
  const auto n = static_cast<std::uint32_t>(mesh.vertices.rows());
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  for (const ChainEdge& e : chain) parent[root(parent, e.a)] = root(parent, e.b);

  // The distinct vertices of each connected part, parts in index order.
  std::vector<bool> onChain(n, false);
  for (const ChainEdge& e : chain) onChain[e.a] = onChain[e.b] = true;
  std::map<std::uint32_t, std::vector<std::uint32_t>> parts;  // by root
  for (std::uint32_t i = 0; i < n; ++i)
    if (onChain[i]) parts[root(parent, i)].push_back(i);

  BoundaryCaps out;
  out.parts = parts.size();
  out.caps.vertices.resize(n + static_cast<Eigen::Index>(parts.size()), 3);
  out.caps.vertices.topRows(n) = mesh.vertices;
  std::map<std::uint32_t, std::uint32_t> centre;
  std::map<std::uint32_t, double> thickness;
  for (const auto& [part, vertices] : parts) {
    centre[part] = n + static_cast<std::uint32_t>(centre.size());
    const PlaneFit fit = fitPlane(mesh.vertices, vertices);
    out.caps.vertices.row(centre[part]) = fit.centre.transpose();
    thickness[part] = fit.thickness;
  }
  // A surplus a -> b is cancelled by the fan triangle (b, a, centre); its
  // edges to the centre cancel within the part, since a boundary has no
  // boundary.
  std::vector<std::array<std::uint32_t, 3>> fans;
  for (const ChainEdge& e : chain) {
    const std::uint32_t part = root(parent, e.a);
    const std::array<std::uint32_t, 3> fan =
        e.net > 0 ? std::array{e.b, e.a, centre[part]} : std::array{e.a, e.b, centre[part]};
    const double fanArea = area(out.caps.vertices, fan[0], fan[1], fan[2]);
    for (int copy = 0; copy < std::abs(e.net); ++copy) {
      fans.push_back(fan);
      out.area += fanArea;
      out.ambiguity += fanArea * thickness[part];
    }
  }
  out.caps.triangles.resize(static_cast<Eigen::Index>(fans.size()), 3);
  for (std::size_t i = 0; i < fans.size(); ++i)
    out.caps.triangles.row(static_cast<Eigen::Index>(i)) << fans[i][0], fans[i][1], fans[i][2];
  return out;
}

CenterOfMass centerOfMass(const TriangleMesh& mesh, bool closed, const ConvexHull& hull) {
  if (closed) {
    const SolidProperties solid = solidProperties(mesh);
    return {solid.centroid, solid.volume, db::CenterOfMassMethod::kClosedMesh};
  }
  const BoundaryCaps caps = boundaryCaps(mesh);
  CenterOfMass out{hull.centroid(),
                   0.0,
                   db::CenterOfMassMethod::kConvexHull,
                   caps.parts,
                   caps.area / surfaceArea(mesh),
                   0.0};
  const SolidProperties solid = solidProperties(withCaps(mesh, caps.caps));
  out.cap_ambiguity = solid.volume > 0.0 ? caps.ambiguity / solid.volume : 0.0;
  // Caps that cancel the mesh (a sheet) leave a volume of rounding noise,
  // and a centroid outside the hull means the caps did not close a solid
  // (e.g. parts wound against each other): then nothing better is known.
  const double hullVolume = solidProperties({hull.vertices(), hull.faces()}).volume;
  if (solid.volume > kMinVolumeOfHull * hullVolume && solid.centroid.allFinite() &&
      hull.depth(solid.centroid) >= 0.0 && out.cap_ambiguity <= kMaxCapAmbiguity) {
    out.point = solid.centroid;
    out.volume = solid.volume;
    out.method = db::CenterOfMassMethod::kRepairedMesh;
  }
  return out;
}

std::string describeCenterOfMass(const CenterOfMass& com, const std::string& what) {
  const auto percent = [](double fraction) {
    std::ostringstream out;
    out << std::setprecision(2) << 100.0 * fraction << " %";
    return out.str();
  };
  const std::string caps = std::to_string(com.cap_parts) + " boundary part" +
                           (com.cap_parts == 1 ? "" : "s") + " capped, caps " +
                           percent(com.cap_area_fraction) +
                           " of the surface, volume ambiguous by " + percent(com.cap_ambiguity);
  switch (com.method) {
    case db::CenterOfMassMethod::kClosedMesh:
      return what + ": the centre of mass is the volume centroid of the closed mesh";
    case db::CenterOfMassMethod::kRepairedMesh:
      return what +
             ": the centre of mass is the volume centroid of the mesh with its boundary "
             "capped (" +
             caps + ")";
    case db::CenterOfMassMethod::kConvexHull:
      break;
  }
  return what +
         ": the centre of mass is the convex hull's centroid, a last resort: capping the "
         "mesh's boundary gives no solid (" +
         caps + ", at most " + percent(kMaxCapAmbiguity) +
         " allowed, and a centroid inside the hull)";
}

}  // namespace hfts::preprocess
