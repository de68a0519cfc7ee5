#pragma once
// How much room a fingertip needs beside a contact, from the robot's own
// collision geometry: used to tell which contacts of a placed object a
// finger cannot touch (grasp/contact_mask.h).

#include "robot/robot_model.h"

namespace hfts::robot {

/// The radius (m) of the largest sphere inside the fingertip link's
/// collision geometry that touches the pad at the fingertip point: its
/// centre lies `radius` behind the point, against the pad normal. A finger
/// whose pad touches a contact holds that sphere, so wherever the sphere
/// cannot be, the finger cannot be either. 0 when the point is not on the
/// surface of one of the link's shapes (searched in steps of 0.1 mm up to
/// 10 cm).
double padRadius(const RobotModel& model, const Fingertip& tip);

/// The smallest padRadius of the robot's fingertips.
double smallestPadRadius(const RobotModel& model);

}  // namespace hfts::robot
