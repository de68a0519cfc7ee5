#pragma once
// From the plan's settings (plan_settings.h) to what the planner's parts
// take, internal to the planner library. (quietOmpl: parameters.h.)

#include "planner/goal_sampler.h"
#include "planner/plan_settings.h"
#include "robot/robot_model.h"

namespace hfts::planner {

/// The motion validator's resolution a space is made with, before the
/// settings' collision_resolution applies (Eq. (3) metric).
constexpr double kTreeResolution = 0.02;

/// What goal sampling takes of the settings; the objective's contact model
/// (soft-finger torsional friction) is the robot's.
GoalSamplingSettings goalSamplingSettings(const PlanSettings& settings,
                                          const robot::RobotModel& robot);

}  // namespace hfts::planner
