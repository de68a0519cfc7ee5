// Mesh import through assimp.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <array>
#include <cmath>
#include <map>

#include "hfts_db/triangle_mesh.h"

namespace hfts {
namespace {

void appendNode(const aiScene& scene, const aiNode& node, TriangleMesh& out,
                std::vector<Eigen::Vector3d>& vertices, std::vector<Eigen::Vector3i>& faces) {
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int offset = static_cast<int>(vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      faces.emplace_back(offset + static_cast<int>(face.mIndices[0]),
                         offset + static_cast<int>(face.mIndices[1]),
                         offset + static_cast<int>(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    appendNode(scene, *node.mChildren[c], out, vertices, faces);
}

/// Merges vertices with identical coordinates. assimp's own joining also
/// compares per-face normals, which leaves STL files split along every
/// crease, so the edge analysis would see every mesh as open.
void weldVertices(std::vector<Eigen::Vector3d>& vertices, std::vector<Eigen::Vector3i>& faces) {
  std::map<std::array<double, 3>, int> index;
  std::vector<Eigen::Vector3d> unique;
  std::vector<int> remap(vertices.size());
  for (std::size_t i = 0; i < vertices.size(); ++i) {
    const std::array<double, 3> key{vertices[i].x(), vertices[i].y(), vertices[i].z()};
    const auto [it, inserted] = index.emplace(key, static_cast<int>(unique.size()));
    if (inserted) unique.push_back(vertices[i]);
    remap[i] = it->second;
  }
  for (Eigen::Vector3i& f : faces)
    for (int k = 0; k < 3; ++k) f[k] = remap[static_cast<std::size_t>(f[k])];
  vertices = std::move(unique);
}

}  // namespace

LoadedMesh loadMesh(const std::filesystem::path& path, double scale) {
  const std::string what = "mesh '" + path.string() + "'";
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw MeshError(what + ": scale must be a positive number");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError(what + ": no such file");
  if (std::filesystem::file_size(path, ec) == 0) throw MeshError(what + ": the file is empty");

  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // PreTransformVertices applies node transforms (and DAE unit scales), so
  // every mesh lands in the file's root frame.
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_PreTransformVertices | aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(path.string(), flags);
  if (scene == nullptr || scene->mRootNode == nullptr)
    throw MeshError(what + ": cannot be read (" + importer.GetErrorString() + ")");

  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
  LoadedMesh loaded;
  appendNode(*scene, *scene->mRootNode, loaded.mesh, vertices, faces);
  if (faces.empty()) throw MeshError(what + ": contains no triangles");
  weldVertices(vertices, faces);

  TriangleMesh& mesh = loaded.mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t i = 0; i < vertices.size(); ++i)
    mesh.vertices.row(static_cast<Eigen::Index>(i)) = scale * vertices[i].transpose();
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    mesh.triangles.row(static_cast<Eigen::Index>(i)) = faces[i].cast<std::uint32_t>().transpose();

  loaded.dropped_degenerate = sanitizeMesh(mesh, what);
  loaded.topology = analyzeTopology(mesh);
  const MeshTopology& t = loaded.topology;
  if (!t.closed())
    loaded.warnings.push_back(what + " is not a closed manifold (" +
                              std::to_string(t.boundary_edges) + " boundary, " +
                              std::to_string(t.non_manifold_edges) + " non-manifold, " +
                              std::to_string(t.inconsistent_edges) +
                              " inconsistently wound edges): the centre of mass is the hull "
                              "centroid, not the volume centroid");
  if (loaded.dropped_degenerate > 0)
    loaded.warnings.push_back(what + ": dropped " + std::to_string(loaded.dropped_degenerate) +
                              " zero-area triangles");
  return loaded;
}

}  // namespace hfts
