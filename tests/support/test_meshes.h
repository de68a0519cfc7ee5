#pragma once
// Small meshes and files for the tests.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "hfts_db/object_database.h"
#include "hfts_db/triangle_mesh.h"

namespace hfts::test {

/// Axis-aligned cube of edge `size` centred at `center`, outward winding.
TriangleMesh cube(double size, const Eigen::Vector3d& center = Eigen::Vector3d::Zero());

/// An object of only a mesh (no contacts, no distance grid): a collision
/// target for the checkers.
db::ObjectGeometry meshObject(const TriangleMesh& mesh);

/// Axis-aligned box from corner `lo` to corner `hi`, outward winding.
TriangleMesh block(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

/// Concatenates two meshes.
TriangleMesh merged(const TriangleMesh& a, const TriangleMesh& b);

/// The same mesh with every triangle's winding reversed.
TriangleMesh flipped(TriangleMesh mesh);

/// A horizontal square of edge `size` at height z (two triangles).
TriangleMesh square(double size, double z);

/// The closed surface of revolution about z of an (r, z) profile that starts
/// and ends on the axis (r = 0) and runs counter-clockwise (the solid on its
/// left), outward wound; `segments` vertices per ring.
TriangleMesh revolved(const std::vector<Eigen::Vector2d>& profile, int segments);

/// A mug-like cup standing on z = 0: outer radius `radius`, height
/// `height`, side wall `wall` and floor `floor` thick, a cavity open at
/// the top; 64 segments, rings every few millimetres (a few thousand
/// triangles).
TriangleMesh cup(double radius = 0.04, double height = 0.1, double wall = 0.005,
                 double floor = 0.006);

/// Distance from p to the nearest point of any triangle, by trying them all.
double bruteForceDistance(const TriangleMesh& mesh, const Eigen::Vector3d& p);

/// Generalised winding number of the mesh around p: the sum of the
/// triangles' signed solid angles over 4 pi (1 inside an outward-wound
/// closed surface, 0 outside, 2 where two closed parts overlap).
double windingNumber(const TriangleMesh& mesh, const Eigen::Vector3d& p);

/// A fresh empty directory under the system temp dir, removed on destruction.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

void writeText(const std::filesystem::path& path, const std::string& text);
std::string readBytes(const std::filesystem::path& path);
void writeBinaryStl(const std::filesystem::path& path, const TriangleMesh& mesh);
void writeAsciiStl(const std::filesystem::path& path, const TriangleMesh& mesh);
void writeObj(const std::filesystem::path& path, const TriangleMesh& mesh);
void writeAsciiPly(const std::filesystem::path& path, const TriangleMesh& mesh);
void writeCollada(const std::filesystem::path& path, const TriangleMesh& mesh);

/// Runs `action` and expects it to throw an `Error` whose message contains
/// every one of `parts` (e.g. the file name and the problem).
template <typename Error, typename Action>
void expectErrorMentioning(Action&& action, const std::vector<std::string>& parts) {
  try {
    action();
    ADD_FAILURE() << "no error; expected one mentioning '" << parts.front() << "'";
  } catch (const Error& e) {
    const std::string message = e.what();
    for (const std::string& part : parts)
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
  }
}

/// The bundled object meshes (objects/meshes).
std::filesystem::path bundledMeshDir();

/// The mesh files of bundledMeshDir(), sorted; not their sidecars (`.json`,
/// preprocess/object_sidecar.h).
std::vector<std::filesystem::path> bundledMeshes();

}  // namespace hfts::test
