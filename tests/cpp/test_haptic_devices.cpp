// SPDX-License-Identifier: GPL-3.0-or-later
// Virtual devices (scripted, host-driven, null) and the workspace map.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "haptics/devices/host_device.h"
#include "haptics/devices/null_device.h"
#include "haptics/devices/scripted_device.h"
#include "haptics/rendering/workspace_map.h"

namespace hf::haptics {
namespace {

void expectVec(const glm::vec3& a, const glm::vec3& b, float tol = 1e-6f) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

ScriptedDevice square(bool loop) {
  return ScriptedDevice({0.0, 1.0, 3.0}, {glm::vec3(0.0f), glm::vec3(0.02f, 0.0f, 0.0f), glm::vec3(0.02f, 0.04f, 0.0f)},
                        loop);
}

TEST(HapticScriptedDevice, InterpolatesLinearlyWithTheSegmentVelocity) {
  const ScriptedDevice d = square(false);
  expectVec(d.stateAt(0.5).position_m, glm::vec3(0.01f, 0.0f, 0.0f));
  expectVec(d.stateAt(0.5).velocity_m_s, glm::vec3(0.02f, 0.0f, 0.0f));
  expectVec(d.stateAt(2.5).position_m, glm::vec3(0.02f, 0.03f, 0.0f));
  expectVec(d.stateAt(2.5).velocity_m_s, glm::vec3(0.0f, 0.02f, 0.0f));
  EXPECT_TRUE(d.stateAt(0.0).homed);
  EXPECT_DOUBLE_EQ(d.durationS(), 3.0);
}

TEST(HapticScriptedDevice, HoldsOrLoopsAtTheEnd) {
  const ScriptedDevice hold = square(false);
  expectVec(hold.stateAt(10.0).position_m, glm::vec3(0.02f, 0.04f, 0.0f));
  expectVec(hold.stateAt(10.0).velocity_m_s, glm::vec3(0.0f));
  const ScriptedDevice loop = square(true);
  expectVec(loop.stateAt(3.5).position_m, glm::vec3(0.01f, 0.0f, 0.0f));  // 3.5 s = 0.5 s into lap 2
  expectVec(loop.stateAt(6.0 + 2.5).position_m, glm::vec3(0.02f, 0.03f, 0.0f));
}

TEST(HapticScriptedDevice, RejectsBadWaypoints) {
  EXPECT_THROW(ScriptedDevice({}, {}, false), InvalidArgument);
  EXPECT_THROW(ScriptedDevice({0.0, 1.0}, {glm::vec3(0.0f)}, false), InvalidArgument);
  EXPECT_THROW(ScriptedDevice({0.0, 0.0}, {glm::vec3(0.0f), glm::vec3(1.0f)}, false), InvalidArgument);
  EXPECT_THROW(ScriptedDevice({0.0}, {glm::vec3(0.0f)}, true), InvalidArgument);
  EXPECT_THROW(ScriptedDevice({0.0}, {glm::vec3(NAN)}, false), InvalidArgument);
  EXPECT_THROW(ScriptedDevice({0.0}, {glm::vec3(0.0f)}, false, 0.0f), InvalidArgument);
}

// The numbers: the looped time rounds up onto the last waypoint. It used to read the
// segment that starts there (one past the end: an out-of-bounds read, a garbage velocity); it is
// the end of the last segment.
TEST(HapticScriptedDevice, ALoopedTimeOnTheLastWaypointIsTheEndOfTheLastSegment) {
  const std::vector<double> times = {63.19510386607734, 66.75379394278342, 70.31248401948949};
  const std::vector<glm::vec3> points = {glm::vec3(0.0f), glm::vec3(0.01f, 0.0f, 0.0f), glm::vec3(0.01f, 0.02f, 0.0f)};
  const ScriptedDevice d(times, points, true);
  const double t = 14.234760306824295;
  ASSERT_EQ(times.front() + std::fmod(times.front() + t - times.front(), d.durationS()), times.back());  // the case
  const DeviceState s = d.stateAt(t);
  const float segment_s = static_cast<float>(times[2] - times[1]);
  expectVec(s.velocity_m_s, glm::vec3(0.0f, 0.02f / segment_s, 0.0f));
  expectVec(s.position_m, points[2]);
}

TEST(HapticScriptedDevice, RefusesANonFiniteTime) {
  for (bool loop : {false, true}) {
    const ScriptedDevice d = square(loop);
    EXPECT_THROW(d.stateAt(INFINITY), InvalidArgument) << loop;
    EXPECT_THROW(d.stateAt(-INFINITY), InvalidArgument) << loop;
    EXPECT_THROW(d.stateAt(NAN), InvalidArgument) << loop;
  }
}

// Waypoints 1e-300 s apart: the velocity would be infinite. (It was computed over the float of
// the span, 0: infinite, or NaN for equal positions; in double equal positions give 0.)
TEST(HapticScriptedDevice, RefusesWaypointsTooCloseForAFiniteVelocity) {
  try {
    ScriptedDevice({0.0, 1e-300}, {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}, false);
    ADD_FAILURE() << "accepted waypoints 1 m and 1e-300 s apart";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("too close in time"), std::string::npos) << e.what();
  }
  const ScriptedDevice still({0.0, 1e-300, 1.0}, {glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f)}, false);
  expectVec(still.stateAt(0.0).velocity_m_s, glm::vec3(0.0f));  // not NaN
  // Close, but the velocity is an ordinary number: accepted.
  const ScriptedDevice ok({0.0, 1e-6}, {glm::vec3(0.0f), glm::vec3(1e-6f, 0.0f, 0.0f)}, false);
  EXPECT_NEAR(ok.stateAt(0.0).velocity_m_s.x, 1.0f, 1e-5f);
}

TEST(HapticScriptedDevice, ReadsACsvFile) {
  const std::string path = ::testing::TempDir() + "hf_script.csv";
  {
    std::ofstream out(path);
    out << "t,x,y,z\n# a comment\n0,0,0,0\n\n2, 0.04, 0, -0.02\n";
  }
  const auto d = ScriptedDevice::fromCsv(path, false);
  expectVec(d->stateAt(1.0).position_m, glm::vec3(0.02f, 0.0f, -0.01f));
  {
    std::ofstream out(path);
    out << "t,x,y,z\n0,0,0,0\n1,2,3\n";
  }
  try {
    ScriptedDevice::fromCsv(path, false);
    FAIL() << "a short row must be rejected";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();  // names the line
  }
  std::remove(path.c_str());
  EXPECT_THROW(ScriptedDevice::fromCsv(path, false), InvalidArgument);  // missing file
}

// A folder or /dev/zero used to read as "holds no t,x,y,z rows" (/dev/zero until memory ran out).
TEST(HapticScriptedDevice, ACsvThatIsAFolderADeviceOrOneHugeLineIsRefused) {
  const auto messageOf = [](const std::string& path) {
    try {
      ScriptedDevice::fromCsv(path, false);
    } catch (const InvalidArgument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(messageOf(::testing::TempDir()).find("is a folder"), std::string::npos) << messageOf(::testing::TempDir());
  EXPECT_NE(messageOf("/dev/zero").find("not a regular file"), std::string::npos) << messageOf("/dev/zero");
  const std::string path = ::testing::TempDir() + "hf_long_line.csv";
  {
    std::ofstream out(path);
    out << "t,x,y,z\n0,0,0,0\n" << std::string(100000, '1') << "\n";
  }
  EXPECT_NE(messageOf(path).find(":3 is longer than 4096 characters"), std::string::npos) << messageOf(path);
  std::remove(path.c_str());
}

TEST(HapticScriptedDevice, ReadFollowsTheClockAndCloseEndsIt) {
  ScriptedDevice d({0.0, 10.0}, {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}, false);
  const DeviceState a = d.read();
  const DeviceState b = d.read();
  EXPECT_GE(b.time_s, a.time_s);
  EXPECT_GE(b.position_m.x, a.position_m.x);
  EXPECT_LT(b.position_m.x, 0.1f);  // time starts at the first read
  d.writeForce(glm::vec3(1.0f, 2.0f, 3.0f));
  expectVec(d.lastForce(), glm::vec3(1.0f, 2.0f, 3.0f));
  d.close();
  d.close();  // idempotent
  EXPECT_THROW(d.read(), Error);
}

TEST(HapticHostDevice, EstimatesVelocityFromSuccessivePushes) {
  HostDevice d;
  EXPECT_FALSE(d.read().homed);  // nothing pushed: no force may be commanded
  d.pushPose(glm::vec3(0.0f), 10.0);
  EXPECT_TRUE(d.stateAfter(0.0).homed);
  expectVec(d.stateAfter(0.0).velocity_m_s, glm::vec3(0.0f));
  d.pushPose(glm::vec3(0.01f, -0.02f, 0.0f), 10.1);
  expectVec(d.stateAfter(0.0).velocity_m_s, glm::vec3(0.1f, -0.2f, 0.0f), 1e-5f);
  // Carried along the velocity between pushes, for at most one push interval (0.1 s).
  expectVec(d.stateAfter(0.05).position_m, glm::vec3(0.015f, -0.03f, 0.0f), 1e-6f);
  expectVec(d.stateAfter(5.0).position_m, glm::vec3(0.02f, -0.04f, 0.0f), 1e-6f);
  EXPECT_EQ(d.pushes(), 2u);
  HostDevice still(10.0f, false);
  still.pushPose(glm::vec3(0.0f), 0.0);
  still.pushPose(glm::vec3(0.01f, 0.0f, 0.0f), 0.1);
  expectVec(still.stateAfter(0.05).position_m, glm::vec3(0.01f, 0.0f, 0.0f));
}

TEST(HapticHostDevice, RejectsTimesThatDoNotIncreaseAndNonFinitePoses) {
  HostDevice d;
  d.pushPose(glm::vec3(0.0f), 1.0);
  EXPECT_THROW(d.pushPose(glm::vec3(0.0f), 1.0), InvalidArgument);
  EXPECT_THROW(d.pushPose(glm::vec3(NAN), 2.0), InvalidArgument);
  d.pushPose(glm::vec3(0.001f, 0.0f, 0.0f), 1.5);  // still usable
  expectVec(d.stateAfter(0.0).velocity_m_s, glm::vec3(0.002f, 0.0f, 0.0f));
  d.close();
  EXPECT_THROW(d.read(), Error);
}

TEST(HapticHostDevice, StateAfterRefusesNaN) {
  HostDevice d(5.0f);
  d.pushPose(glm::vec3(0.0f), 1.0);
  d.pushPose(glm::vec3(0.01f, 0.0f, 0.0f), 1.1);
  EXPECT_THROW(d.stateAfter(NAN), InvalidArgument);
  const DeviceState s = d.stateAfter(INFINITY);  // extrapolated for one push interval at most
  EXPECT_NEAR(s.position_m.x, 0.02f, 1e-6f);
}

TEST(HapticNullDevice, RestsHomedAndDiscards) {
  NullDevice d;
  const DeviceState s = d.read();
  EXPECT_TRUE(s.homed);
  expectVec(s.position_m, glm::vec3(0.0f));
  EXPECT_EQ(d.info().kind, "null");
  d.writeForce(glm::vec3(100.0f));
  d.close();
  EXPECT_THROW(d.read(), Error);
  EXPECT_THROW(NullDevice(-1.0f), InvalidArgument);
}

TEST(HapticWorkspaceMap, MapsPoseIntoTheDomainAndForceBack) {
  WorkspaceMap m;
  m.scale = glm::vec3(5.0f, -5.0f, 5.0f);
  m.offset_m = glm::vec3(0.5f);
  m.force_gain = 0.5f;
  expectVec(m.positionToDomain(glm::vec3(0.02f, 0.02f, -0.04f)), glm::vec3(0.6f, 0.4f, 0.3f));
  expectVec(m.velocityToDomain(glm::vec3(0.1f, 0.1f, 0.0f)), glm::vec3(0.5f, -0.5f, 0.0f));
  // The flipped y axis is flipped back for the force, so it pushes the hand the same way.
  expectVec(m.forceToDevice(glm::vec3(2.0f, 2.0f, -4.0f)), glm::vec3(1.0f, -1.0f, -2.0f));
  // ... and the device's force read back in the domain's axes has the fluid force's direction
  // (the same device newtons: no gain undone).
  expectVec(m.forceToDomainAxes(glm::vec3(1.0f, -1.0f, -2.0f)), glm::vec3(1.0f, 1.0f, -2.0f));
  m.scale.y = 0.0f;
  EXPECT_THROW(m.validate(), InvalidArgument);
  m.scale.y = 1.0f;
  m.force_gain = -1.0f;
  EXPECT_THROW(m.validate(), InvalidArgument);
}

}  // namespace
}  // namespace hf::haptics
