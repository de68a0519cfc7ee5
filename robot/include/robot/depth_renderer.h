#pragma once
// Synthetic depth images of a scene (docs/point_clouds.md): what a depth
// camera at a pose would see of the obstacles and the target object, with
// a sensor's noise, and which pixels see the target (the segmentation a
// perception pipeline would give). Ray casting with Embree (db::TriangleBvh).

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "hfts_db/triangle_mesh.h"
#include "robot/point_cloud.h"
#include "robot/scene.h"

namespace hfts::robot {

/// A structured-light camera's errors, after Nguyen, Izadi and Lovell,
/// "Modeling Kinect Sensor Noise for Improved 3D Reconstruction and
/// Tracking" (3DIMPVT 2012): axial noise sigma(z) = base + quadratic (z -
/// centre)^2 (m), no reading where the surface is seen at more than
/// `max_incidence` from its normal, and pixels lost at random.
struct DepthNoise {
  double sigma_base = 0.0012;
  double sigma_quadratic = 0.0019;
  double sigma_centre = 0.4;
  double max_incidence = 1.3089969389957472;  ///< rad (75 degrees)
  double dropout = 0.01;                      ///< fraction of the other pixels lost
  std::uint64_t seed = 1;

  /// Exact depths everywhere the camera sees a surface.
  static DepthNoise none() { return {0.0, 0.0, 0.0, 2.0, 0.0, 1}; }
};

/// A camera: its intrinsics and depth range, its image size and its
/// optical frame's pose in the world (x right, y down, z along the view).
struct DepthView {
  DepthCamera camera;
  int width = 640;
  int height = 480;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();

  /// A camera with a horizontal field of view `fov` (rad), the principal
  /// point at the image's centre.
  static DepthView withFieldOfView(int width, int height, double fov);
};

/// The optical frame of a camera at `eye` looking at `centre`, its image's
/// rows (y) pointing down in the world where they can.
Eigen::Isometry3d lookAt(const Eigen::Vector3d& eye, const Eigen::Vector3d& centre);

struct RenderedDepth {
  DepthImage image;
  /// 1 where the pixel sees the target, as image.depths.
  std::vector<std::uint8_t> target_mask;
};

/// Renders the scene's obstacles (a cloud as its voxels' boxes) and, when
/// given, the target's mesh (its frame) at `targetPose`. Throws
/// hfts::InvalidArgument ("view") for an image of no pixels or more than
/// 4096 x 4096, or a camera without positive focal lengths.
RenderedDepth renderDepth(const Scene& scene, const TriangleMesh* target,
                          const Eigen::Isometry3d& targetPose, const DepthView& view,
                          const DepthNoise& noise);

}  // namespace hfts::robot
