#include "service/validation_json.h"

#include <nlohmann/json.hpp>

#include "json_fields.h"
#include "json_geometry.h"

namespace hfts::service {

using nlohmann::json;

json graspCheckToJson(const planner::GraspCheck& check) {
  return {{"valid", check.valid()},
          {"problem", check.problem},
          {"pads_touch", check.pads_touch},
          {"epsilon", check.epsilon},
          {"load_capacity", check.load_capacity ? json(*check.load_capacity) : json(nullptr)},
          {"penetration", check.penetration},
          {"clear", check.clear},
          {"closing_difference", check.closing_difference}};
}

json physicsToJson(const physics::GraspVerdict& verdict, bool motion) {
  json trials = json::array();
  for (const physics::TrialResult& t : verdict.trials)
    trials.push_back({{"name", t.name},
                      {"held", t.held},
                      {"failure", t.failure},
                      {"max_displacement", t.max_displacement},
                      {"max_rotation", t.max_rotation},
                      {"fingers_in_contact", t.fingers_in_contact},
                      {"simulated_time", t.simulated_time}});
  json out = {{"held", verdict.held},
              {"held_fraction", verdict.held_fraction},
              {"mass", verdict.mass},
              {"density", verdict.density},
              {"collision_shape", verdict.collision_shape},
              {"shape_fidelity", verdict.shape_fidelity},
              {"lift_direction", verdict.lift_direction},
              {"trials", std::move(trials)}};
  if (!motion) return out;
  json samples = json::array();
  for (const physics::MotionSample& s : verdict.nominal_motion)
    samples.push_back({{"time", s.time}, {"phase", s.phase}, {"pose", poseJson(s.object)}});
  out["motion"] = std::move(samples);
  return out;
}

json placePhysicsToJson(const physics::PlaceVerdict& v) {
  json motion = json::array();
  for (const physics::MotionSample& s : v.motion)
    motion.push_back({{"time", s.time}, {"phase", s.phase}, {"pose", poseJson(s.object)}});
  return {{"held", v.held},
          {"placed", v.placed},
          {"stood", v.stood},
          {"failure", v.failure},
          {"max_displacement", v.max_displacement},
          {"max_rotation", v.max_rotation},
          {"rest_displacement", v.rest_displacement},
          {"rest_rotation", v.rest_rotation},
          {"stand_displacement", v.stand_displacement},
          {"stand_rotation", v.stand_rotation},
          {"place_displacement", v.place_displacement},
          {"place_rotation", v.place_rotation},
          {"simulated_time", v.simulated_time},
          {"motion", std::move(motion)}};
}

planner::ValidationRequest validationRequestFromPlan(const json& plan, robot::Scene scene,
                                                     const robot::RobotModel& robot) {
  const JsonFields f(plan, "");
  if (!f.boolean("success")) f.fail("success", "the plan failed: it has no grasp to validate");
  const json& path = f.at("path");
  if (!path.is_array() || path.size() < 2)
    f.fail("path", "must hold the pre-grasp and the grasp at its end");
  planner::ValidationRequest r;
  const json ends = {{"pregrasp", path[path.size() - 2]}, {"grasp", path.back()}};
  const JsonFields last(ends, "path");
  r.pregrasp = last.numbers("pregrasp", robot.numDofs());
  r.grasp = last.numbers("grasp", robot.numDofs());
  if (f.has("object") && !f.string("object").empty()) scene.target_object = f.name("object");
  scene.target_pose = f.pose("object_pose");
  scene.target_rest_on.clear();
  r.scene = std::move(scene);
  return r;
}

}  // namespace hfts::service
