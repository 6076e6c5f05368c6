// Rostest: a bad private parameter fails at start with a message that names it, from a node of its
// own (which exits) and from a manager (which logs it and stays).
#include <gtest/gtest.h>

#include <string>

#include <ros/ros.h>
#include <ros/service.h>
#include <sl_testing/child_process.h>
#include <sl_testing/process.h>
#include <sl_testing/rostest_main.h>

namespace
{
/// Runs `rosrun create_driver <node> <args>`; expects it to exit with an error naming @p name.
void expectExitNaming(const std::string& node, const std::string& args, const std::string& name)
{
  std::string out;
  const int status = sl_testing::run("timeout 90 rosrun create_driver " + node + " " + args, out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(status, 124) << "the node did not exit:\n" << out;
  EXPECT_NE(out.find(name), std::string::npos) << out;
  EXPECT_NE(out.find("could not load the create_driver/"), std::string::npos) << out;
}

TEST(DriverParams, DriverNodeExitsNamingTheParameter)
{
  expectExitNaming("create_driver_node", "__name:=bad_driver0 _max_speed:=-1", "~max_speed must be in (0, 0.5]");
  expectExitNaming("create_driver_node", "__name:=bad_driver1 _oi_mode:=fast", "~oi_mode");
  expectExitNaming("create_driver_node", "__name:=bad_driver2 _baud:=fast", "~baud must be an integer");
}

TEST(DriverParams, SimNodeExitsNamingTheParameter)
{
  expectExitNaming("create_sim", "__name:=bad_sim0 _wheel_base:=2.0", "~wheel_base must be in");
  expectExitNaming("create_sim", "__name:=bad_sim1 _link:=/no/such/dir/create", "~link: ");
}

TEST(DriverParams, NodeletInAManagerLogsTheParameterThere)
{
  sl_testing::Child manager({ "rosrun", "nodelet", "nodelet", "manager", "__name:=driver_params_manager" });
  ASSERT_TRUE(ros::service::waitForService("driver_params_manager/load_nodelet", ros::Duration(60.0)))
      << manager.output();
  std::string out;
  const int status = sl_testing::run(
      "timeout 90 rosrun nodelet nodelet load create_driver/driver "
      "driver_params_manager __name:=bad_driver_in_manager _max_speed:=0.9",
      out);
  EXPECT_NE(status, 0) << "the load was accepted:\n" << out;
  EXPECT_TRUE(manager.readUntil({ "invalid parameter: ~max_speed must be in (0, 0.5]" }, 60.0)) << manager.output();
  EXPECT_TRUE(manager.running()) << manager.output();
}
}  // namespace

int main(int argc, char** argv)
{
  return sl_testing::runRostests(argc, argv, "driver_params_rostest", 0);
}
