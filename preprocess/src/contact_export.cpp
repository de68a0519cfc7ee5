#include "preprocess/contact_export.h"

#include <cmath>
#include <sstream>

#include "core/atomic_file.h"

namespace hfts::preprocess {

std::array<unsigned char, 3> clusterColour(std::size_t index) {
  // Golden-ratio hue steps keep consecutive clusters far apart on the wheel.
  const double hue = std::fmod(0.61803398875 * static_cast<double>(index), 1.0) * 6.0;
  const double saturation = index % 2 == 0 ? 0.85 : 0.6;
  const double value = index % 3 == 0 ? 0.95 : 0.8;
  const int sector = static_cast<int>(hue);
  const double f = hue - sector;
  const double p = value * (1 - saturation), q = value * (1 - saturation * f),
               t = value * (1 - saturation * (1 - f));
  const double rgb[6][3] = {{value, t, p}, {q, value, p}, {p, value, t},
                            {p, q, value}, {t, p, value}, {value, p, q}};
  std::array<unsigned char, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<unsigned char>(std::lround(255.0 * rgb[sector % 6][c]));
  return out;
}

void exportContactsPly(const db::ObjectDatabase& db, const std::filesystem::path& path) {
  std::ostringstream out;
  out.precision(9);
  out << "ply\nformat ascii 1.0\ncomment hfts contacts of '" << db.name
      << "', coloured by top-level cluster\nelement vertex " << db.numContacts()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
         "property float nx\nproperty float ny\nproperty float nz\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  const std::vector<db::HierarchyNode>& top = db.levels.front();
  for (std::size_t cluster = 0; cluster < top.size(); ++cluster) {
    const auto colour = clusterColour(cluster);
    const db::HierarchyNode& node = top[cluster];
    for (std::uint32_t i = node.contact_begin; i < node.contact_begin + node.contact_count; ++i) {
      out << db.positions(i, 0) << ' ' << db.positions(i, 1) << ' ' << db.positions(i, 2) << ' '
          << db.normals(i, 0) << ' ' << db.normals(i, 1) << ' ' << db.normals(i, 2) << ' '
          << int{colour[0]} << ' ' << int{colour[1]} << ' ' << int{colour[2]} << '\n';
    }
  }
  core::writeFileAtomically(path, out.str());
}

}  // namespace hfts::preprocess
