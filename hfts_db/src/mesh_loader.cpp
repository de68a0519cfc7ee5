// Mesh import through assimp.
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>

#include "hfts_db/isolated_call.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts {
namespace {

/// What the importer found: vertices and triangles of every mesh of the
/// scene graph, in the file's root frame.
struct ImportedMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Eigen::Vector3i> faces;
};

void appendNode(const aiScene& scene, const aiNode& node, ImportedMesh& out) {
  for (unsigned m = 0; m < node.mNumMeshes; ++m) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
    const int offset = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines carry no surface
      out.faces.emplace_back(offset + static_cast<int>(face.mIndices[0]),
                             offset + static_cast<int>(face.mIndices[1]),
                             offset + static_cast<int>(face.mIndices[2]));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) appendNode(scene, *node.mChildren[c], out);
}

/// Runs assimp on the file (in the child process of importMesh). Throws
/// std::runtime_error with assimp's message when it refuses the file.
ImportedMesh importWithAssimp(const std::filesystem::path& path) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // ValidateDataStructure runs before the other steps: assimp's importers
  // pass some malformed files through (a PLY face naming a vertex that does
  // not exist), and the later steps would read out of bounds on them.
  // PreTransformVertices applies node transforms (and DAE unit scales), so
  // every mesh lands in the file's root frame.
  const unsigned flags = aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                         aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType;
  const aiScene* scene = importer.ReadFile(path.string(), flags);
  if (scene == nullptr || scene->mRootNode == nullptr)
    throw std::runtime_error(importer.GetErrorString());
  ImportedMesh out;
  appendNode(*scene, *scene->mRootNode, out);
  return out;
}

// The child hands the mesh over as two counts, then the coordinates and
// the vertex indices in machine order (same program, same machine).
std::string serialize(const ImportedMesh& m) {
  const std::uint64_t counts[2] = {m.vertices.size(), m.faces.size()};
  std::string bytes(
      sizeof counts + m.vertices.size() * 3 * sizeof(double) + m.faces.size() * 3 * sizeof(int),
      '\0');
  char* out = bytes.data();
  std::memcpy(out, counts, sizeof counts);
  out += sizeof counts;
  for (const Eigen::Vector3d& v : m.vertices) {
    std::memcpy(out, v.data(), 3 * sizeof(double));
    out += 3 * sizeof(double);
  }
  for (const Eigen::Vector3i& f : m.faces) {
    std::memcpy(out, f.data(), 3 * sizeof(int));
    out += 3 * sizeof(int);
  }
  return bytes;
}

ImportedMesh deserialize(const std::string& bytes) {
  std::uint64_t counts[2];
  if (bytes.size() < sizeof counts) throw std::runtime_error("truncated import result");
  std::memcpy(counts, bytes.data(), sizeof counts);
  const std::uint64_t vertexBytes = 3 * sizeof(double), faceBytes = 3 * sizeof(int);
  const std::uint64_t rest = bytes.size() - sizeof counts;
  if (counts[0] > rest / vertexBytes || counts[1] > rest / faceBytes ||
      counts[0] * vertexBytes + counts[1] * faceBytes != rest)
    throw std::runtime_error("inconsistent import result");
  ImportedMesh m;
  m.vertices.resize(counts[0]);
  m.faces.resize(counts[1]);
  const char* in = bytes.data() + sizeof counts;
  for (Eigen::Vector3d& v : m.vertices) {
    std::memcpy(v.data(), in, vertexBytes);
    in += vertexBytes;
  }
  for (Eigen::Vector3i& f : m.faces) {
    std::memcpy(f.data(), in, faceBytes);
    in += faceBytes;
  }
  return m;
}

/// assimp in a child process: some malformed files make its importers
/// read out of bounds (docs/reliability.md), and a user's bad file must
/// give an error, not end the program (or the server loading a scene).
ImportedMesh importMesh(const std::filesystem::path& path, const std::string& what,
                        const IsolationLimits& limits) {
  try {
    return deserialize(runIsolated([&] { return serialize(importWithAssimp(path)); }, limits));
  } catch (const IsolatedCallError& e) {
    if (e.kind() == IsolatedCallError::Kind::kThrew)
      throw MeshError(what + ": cannot be read (" + e.what() + ")");
    throw MeshError(what + ": the mesh importer (assimp) failed on it: " + e.what() +
                    "; the file is malformed or uses a feature assimp cannot read");
  } catch (const std::runtime_error& e) {
    throw MeshError(what + ": cannot be read (" + e.what() + ")");
  }
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

IsolationLimits meshImportLimits(std::uintmax_t fileBytes) {
  IsolationLimits limits;
  limits.time = std::chrono::seconds(60) + std::chrono::milliseconds(fileBytes * 1000 >> 20);
  limits.extra_memory_bytes = (std::size_t{2} << 30) + 64 * fileBytes;
  return limits;
}

LoadedMesh loadMesh(const std::filesystem::path& path, double scale,
                    const std::optional<IsolationLimits>& limits) {
  const std::string what = "mesh '" + path.string() + "'";
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw MeshError(what + ": scale must be a positive number");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw MeshError(what + ": no such file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw MeshError(what + ": cannot be read (" + ec.message() + ")");
  if (size == 0) throw MeshError(what + ": the file is empty");

  ImportedMesh imported = importMesh(path, what, limits ? *limits : meshImportLimits(size));
  std::vector<Eigen::Vector3d>& vertices = imported.vertices;
  std::vector<Eigen::Vector3i>& faces = imported.faces;
  LoadedMesh loaded;
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
    loaded.warnings.push_back(
        what + " is not a closed manifold (" + std::to_string(t.boundary_edges) + " boundary, " +
        std::to_string(t.non_manifold_edges) + " non-manifold, " +
        std::to_string(t.inconsistent_edges) + " inconsistently wound edges)");
  if (loaded.dropped_degenerate > 0)
    loaded.warnings.push_back(what + ": dropped " + std::to_string(loaded.dropped_degenerate) +
                              " zero-area triangles");
  return loaded;
}

}  // namespace hfts
