#pragma once
// Private to physics/src: a minimal XML element tree for writing MJCF, and
// the number formats MuJoCo reads (locale-independent, 12 digits: below a
// micrometre at any scene size).

#include <Eigen/Geometry>

#include <locale>
#include <memory>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace hfts::physics {

inline std::string number(double value) {
  std::ostringstream out;
  out.imbue(std::locale::classic());
  out.precision(12);
  out << value;
  return out.str();
}

/// The coefficients of a vector or matrix (column-major), space-separated.
template <typename Derived>
std::string numbers(const Eigen::MatrixBase<Derived>& values) {
  std::string out;
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (i > 0) out += ' ';
    out += number(values(i));
  }
  return out;
}

/// The rows of an n x 3 matrix one after another (MJCF vertex lists).
template <typename Derived>
std::string rowNumbers(const Eigen::MatrixBase<Derived>& rows) {
  std::string out;
  for (Eigen::Index r = 0; r < rows.rows(); ++r)
    for (Eigen::Index c = 0; c < rows.cols(); ++c) {
      if (!out.empty()) out += ' ';
      out += number(rows(r, c));
    }
  return out;
}

class XmlElement {
 public:
  explicit XmlElement(std::string name) : name_(std::move(name)) {}

  XmlElement& attribute(const std::string& key, const std::string& value) {
    attributes_.emplace_back(key, value);
    return *this;
  }
  XmlElement& attribute(const std::string& key, const char* value) {
    return attribute(key, std::string(value));
  }
  XmlElement& attribute(const std::string& key, int value) {
    return attribute(key, std::to_string(value));
  }
  /// A new last child element.
  XmlElement& child(const std::string& name) {
    children_.push_back(std::make_unique<XmlElement>(name));
    return *children_.back();
  }

  void write(std::ostream& out, int indent) const {
    out << std::string(static_cast<std::size_t>(indent), ' ') << '<' << name_;
    for (const auto& [key, value] : attributes_)
      out << ' ' << key << "=\"" << escaped(value) << '"';
    if (children_.empty()) {
      out << "/>\n";
      return;
    }
    out << ">\n";
    for (const auto& child : children_) child->write(out, indent + 2);
    out << std::string(static_cast<std::size_t>(indent), ' ') << "</" << name_ << ">\n";
  }

 private:
  static std::string escaped(const std::string& text) {
    std::string out;
    for (char c : text) {
      switch (c) {
        case '&':
          out += "&amp;";
          break;
        case '<':
          out += "&lt;";
          break;
        case '>':
          out += "&gt;";
          break;
        case '"':
          out += "&quot;";
          break;
        default:
          out += c;
      }
    }
    return out;
  }

  std::string name_;
  std::vector<std::pair<std::string, std::string>> attributes_;
  std::vector<std::unique_ptr<XmlElement>> children_;
};

/// pos and quat (w x y z) of a frame.
inline void writePose(XmlElement& element, const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  element.attribute("pos", numbers(pose.translation()))
      .attribute("quat", numbers(Eigen::Vector4d(q.w(), q.x(), q.y(), q.z())));
}

/// An <inertial>: mass (kg) and the inertia tensor (kg m^2) about the
/// centre of mass, both given in the frame `origin` of the body. MJCF's
/// fullinertia excludes a quat: the tensor is turned into the body's axes.
inline void writeInertialElement(XmlElement& inertial, double mass, const Eigen::Isometry3d& origin,
                                 const Eigen::Matrix3d& inertia) {
  const Eigen::Matrix3d i = origin.linear() * inertia * origin.linear().transpose();
  inertial.attribute("pos", numbers(origin.translation()))
      .attribute("mass", number(mass))
      .attribute("fullinertia", numbers(Eigen::Matrix<double, 6, 1>(i(0, 0), i(1, 1), i(2, 2),
                                                                    i(0, 1), i(0, 2), i(1, 2))));
}

}  // namespace hfts::physics
