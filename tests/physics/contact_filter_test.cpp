#include "contact_filter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "mujoco_world.h"

namespace hfts::physics {
namespace {

/// A geom of each type, turned, for distances to a point.
constexpr const char* kShapes = R"(<mujoco><worldbody>
  <geom name='box' type='box' size='0.1 0.2 0.3' pos='1 0 0' euler='0 0 90'/>
  <geom name='capsule' type='capsule' size='0.05 0.2' pos='0 1 0' euler='90 0 0'/>
  <geom name='cylinder' type='cylinder' size='0.05 0.2' pos='0 0 1'/>
  <geom name='sphere' type='sphere' size='0.1' pos='-1 0 0'/>
</worldbody></mujoco>)";

struct Compiled {
  explicit Compiled(const std::string& xml) : model(compileMjcf(xml)), data(makeData(*model)) {
    mj_forward(model.get(), data.get());
  }
  int geom(const char* name) const { return mj_name2id(model.get(), mjOBJ_GEOM, name); }
  double distance(const char* name, double x, double y, double z, double radius) const {
    const mjtNum centre[3] = {x, y, z};
    return sphereToGeom(*model, *data, geom(name), centre, radius);
  }
  ModelPtr model;
  DataPtr data;
};

TEST(ContactFilter, SphereToShapeDistancesAreExact) {
  const Compiled c(kShapes);
  // The box turned 90 degrees about z: its 0.2 half extent lies along x.
  EXPECT_NEAR(c.distance("box", 1.5, 0, 0, 0.1), 0.5 - 0.2 - 0.1, 1e-12);
  EXPECT_NEAR(c.distance("box", 1, 0.5, 0, 0.0), 0.5 - 0.1, 1e-12);
  EXPECT_NEAR(c.distance("box", 1.2 + 0.3, 0.1 + 0.4, 0, 0.0), 0.5, 1e-12);
  EXPECT_LT(c.distance("box", 1, 0, 0, 0.01), 0.0);
  // The capsule's axis along world y (its z turned by 90 degrees about x).
  EXPECT_NEAR(c.distance("capsule", 0, 1.5, 0, 0.0), 0.5 - 0.2 - 0.05, 1e-12);
  EXPECT_NEAR(c.distance("capsule", 0.3, 1.1, 0, 0.0), 0.3 - 0.05, 1e-12);
  // The cylinder: its flat ends are not rounded.
  EXPECT_NEAR(c.distance("cylinder", 0.05 + 0.3, 0, 1.2 + 0.4, 0.0), 0.5, 1e-12);
  EXPECT_NEAR(c.distance("cylinder", 0.04, 0, 1.5, 0.0), 0.3, 1e-12);
  EXPECT_NEAR(c.distance("sphere", -1, 0.5, 0, 0.1), 0.3, 1e-12);
}

/// A free body of many small convex meshes (a bowl-like ring) dropped on a
/// wide table top, pressed by a capsule and a cylinder on sliders.
std::string ringScene() {
  std::ostringstream xml;
  xml << "<mujoco><option timestep='0.002'><flag multiccd='enable'/></option><asset>";
  xml << "<mesh name='piece' vertex='-0.01 -0.005 -0.01 0.01 -0.005 -0.01 -0.01 0.005 -0.01 "
         "0.01 0.005 -0.01 -0.008 -0.004 0.01 0.008 -0.004 0.01 -0.008 0.004 0.01 0.008 0.004 "
         "0.01'/></asset><worldbody>";
  xml << "<geom name='table' type='box' size='0.6 0.4 0.02' pos='0 0 -0.02' contype='4' "
         "conaffinity='1'/>";
  xml << "<body name='ring' pos='0 0 0.02'><freejoint/>";
  for (int i = 0; i < 48; ++i) {
    const double a = 2.0 * M_PI * i / 48.0;
    xml << "<geom type='mesh' mesh='piece' contype='2' conaffinity='5' pos='" << 0.06 * std::cos(a)
        << ' ' << 0.06 * std::sin(a) << " " << 0.01 * (i % 3) << "' euler='0 0 "
        << a * 180.0 / M_PI + 90.0 << "'/>";
  }
  xml << "</body>";
  xml << "<body name='pusher' pos='0.2 0 0.02'><joint name='push' type='slide' axis='-1 0 0'/>"
         "<geom type='capsule' size='0.01 0.03' euler='90 0 0' contype='1' conaffinity='0'/>"
         "<geom type='cylinder' size='0.01 0.02' pos='0 0 0.04' contype='1' conaffinity='0'/>"
         "</body></worldbody>";
  xml << "<actuator><position joint='push' kp='50'/></actuator></mujoco>";
  return xml.str();
}

TEST(ContactFilter, TheSimulationIsTheSameWithAndWithoutIt) {
  const ModelPtr model = compileMjcf(ringScene());
  const auto run = [&](mjfConFilt filter, int* discarded) {
    const mjfConFilt before = mjcb_contactfilter;
    mjcb_contactfilter = filter;
    const DataPtr data = makeData(*model);
    std::vector<double> trace;
    for (int step = 0; step < 600; ++step) {
      data->ctrl[0] = step < 100 ? 0.0 : 0.12;  // the pusher reaches the ring
      mj_step(model.get(), data.get());
      for (int i = 0; i < model->nq; ++i) trace.push_back(data->qpos[i]);
      trace.push_back(data->ncon);
    }
    mjcb_contactfilter = before;
    if (discarded != nullptr) {
      // Pairs the filter drops beyond MuJoCo's own sphere test, at the end.
      *discarded = 0;
      for (int a = 0; a < model->ngeom; ++a)
        for (int b = a + 1; b < model->ngeom; ++b)
          if (model->geom_bodyid[a] != model->geom_bodyid[b] &&
              filterContactPair(model.get(), data.get(), a, b) != 0)
            ++*discarded;
    }
    return trace;
  };
  int discarded = 0;
  const std::vector<double> plain = run(nullptr, nullptr);
  const std::vector<double> filtered = run(filterContactPair, &discarded);
  ASSERT_EQ(plain.size(), filtered.size());
  for (std::size_t i = 0; i < plain.size(); ++i) ASSERT_EQ(plain[i], filtered[i]) << i;
  EXPECT_GT(discarded, 0);
  // The ring rests on the table and the pusher touches it: contacts exist.
  EXPECT_GT(plain.back(), 0.0);
}

TEST(ContactFilter, PairsOfGroupsThatDoNotTouchAreDiscarded) {
  const Compiled c(R"(<mujoco><worldbody>
    <geom name='a' type='sphere' size='0.1' contype='1' conaffinity='0'/>
    <geom name='b' type='sphere' size='0.1' pos='0.05 0 0' contype='1' conaffinity='0'/>
    <geom name='c' type='sphere' size='0.1' pos='0.05 0 0' contype='2' conaffinity='1'/>
  </worldbody></mujoco>)");
  EXPECT_EQ(filterContactPair(c.model.get(), c.data.get(), c.geom("a"), c.geom("b")), 1);
  EXPECT_EQ(filterContactPair(c.model.get(), c.data.get(), c.geom("a"), c.geom("c")), 0);
}

TEST(ContactFilter, ASphereFarFromABoxCornerIsDiscardedThoughTheBoundingSpheresOverlap) {
  const Compiled c(R"(<mujoco><worldbody>
    <geom name='table' type='box' size='0.5 0.5 0.01'/>
    <geom name='ball' type='sphere' size='0.02' pos='0.4 0.4 0.1'/>
    <geom name='near' type='sphere' size='0.02' pos='0.4 0.4 0.029'/>
  </worldbody></mujoco>)");
  EXPECT_EQ(filterContactPair(c.model.get(), c.data.get(), c.geom("table"), c.geom("ball")), 1);
  EXPECT_EQ(filterContactPair(c.model.get(), c.data.get(), c.geom("table"), c.geom("near")), 0);
}

}  // namespace
}  // namespace hfts::physics
