#include "core/sensor/virtual_device_uri.h"

#include <gtest/gtest.h>

namespace icgm {
namespace {

TEST(VirtualDeviceUri, ParsesTheTumSource) {
  VirtualDeviceConfig c;
  ASSERT_TRUE(ParseVirtualDeviceUri("icgm-virtual://tum?dir=/d/x&frames=100&rate=0.5&loop=1", &c).ok());
  EXPECT_EQ(c.source, "tum");
  EXPECT_EQ(c.dir, "/d/x");
  EXPECT_EQ(c.max_frames, 100);
  EXPECT_DOUBLE_EQ(c.rate, 0.5);
  EXPECT_TRUE(c.loop);
  EXPECT_TRUE(c.camera_yaml.empty());
}

TEST(VirtualDeviceUri, ParsesTheSimulatorSource) {
  VirtualDeviceConfig c;
  ASSERT_TRUE(ParseVirtualDeviceUri("icgm-virtual://sim?scenario=/c/s.yaml&frames=5&loop=1", &c).ok());
  EXPECT_EQ(c.source, "sim");
  EXPECT_EQ(c.scenario, "/c/s.yaml");
  EXPECT_EQ(c.max_frames, 5);
  EXPECT_TRUE(c.loop);
  const Status no_scenario = ParseVirtualDeviceUri("icgm-virtual://sim?frames=5", &c);
  ASSERT_FALSE(no_scenario.ok());
  EXPECT_NE(no_scenario.reason().find("scenario="), std::string::npos) << no_scenario.reason();
  // Each source takes only its own parameters.
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://sim?scenario=/s.yaml&camera=/k.yaml", &c).ok());
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://tum?dir=/d&scenario=/s.yaml", &c).ok());
}

TEST(VirtualDeviceUri, RejectsWithAReason) {
  VirtualDeviceConfig c;
  EXPECT_FALSE(IsVirtualDeviceUri("/tmp/a.oni"));
  const Status s = ParseVirtualDeviceUri("icgm-virtual://tum?dir=/d&fps=30", &c);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.reason().find("unknown parameter 'fps'"), std::string::npos) << s.reason();
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://tum?frames=3", &c).ok());  // no dir
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://sim?dir=/d", &c).ok());
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://cam?dir=/d", &c).ok());
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://tum?dir=/d&rate=0", &c).ok());
  EXPECT_FALSE(ParseVirtualDeviceUri("icgm-virtual://tum?dir=/d&frames=-2", &c).ok());
}

}  // namespace
}  // namespace icgm
