// Checks the projector nodelet in a running system: latched pattern and camera_info, and that bad
// parameters stop the node with a message naming the parameter.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <csignal>
#include <cstdio>
#include <fcntl.h>
#include <stdexcept>
#include <string>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

namespace
{
template <typename M>
typename M::ConstPtr waitFor(const std::string& topic, double timeout)
{
  return ros::topic::waitForMessage<M>(topic, ros::Duration(timeout));
}

// Runs a command, returns its exit status and combined output.
int run(const std::string& command, std::string& output)
{
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe)
    return -1;
  std::array<char, 512> buf;
  while (fgets(buf.data(), buf.size(), pipe))
    output += buf.data();
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// A command run in its own process group with stdout and stderr on one pipe, read while it runs.
class Child
{
public:
  explicit Child(const std::vector<std::string>& args)
  {
    // Built before fork(): the child of a threaded process may only make async-signal-safe calls.
    std::vector<char*> argv;
    for (const std::string& a : args)
      argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
      throw std::runtime_error("pipe2 failed");
    pid_ = fork();
    if (pid_ == 0)
    {
      setpgid(0, 0);
      dup2(fds[1], STDOUT_FILENO);
      dup2(fds[1], STDERR_FILENO);
      execvp(argv[0], argv.data());
      _exit(127);
    }
    setpgid(pid_, pid_);  // as in the child: whichever runs first
    close(fds[1]);
    fd_ = fds[0];
    fcntl(fd_, F_SETFL, O_NONBLOCK);
  }
  ~Child()
  {
    if (pid_ > 0 && !exited_)
    {
      kill(-pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (fd_ >= 0)
      close(fd_);
  }

  /// Reads the output until it contains every one of @p texts, the child ends, or @p give_up_s pass.
  bool readUntil(const std::vector<std::string>& texts, double give_up_s)
  {
    const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(give_up_s);
    while (ros::WallTime::now() < give_up)
    {
      drain();
      if (std::all_of(texts.begin(), texts.end(),
                      [&](const std::string& t) { return output_.find(t) != std::string::npos; }))
        return true;
      if (!running())
        break;
      ros::WallDuration(0.05).sleep();
    }
    drain();
    return false;
  }
  bool running()
  {
    if (exited_)
      return false;
    exited_ = waitpid(pid_, &status_, WNOHANG) == pid_;
    return !exited_;
  }
  /// SIGINT (as roslaunch stops a node), then its exit status; -1 if it did not exit normally.
  int interrupt()
  {
    if (running())
    {
      kill(-pid_, SIGINT);
      waitpid(pid_, &status_, 0);
      exited_ = true;
    }
    drain();
    return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
  }
  const std::string& output()
  {
    drain();
    return output_;
  }

private:
  void drain()
  {
    char buf[512];
    ssize_t n;
    while ((n = read(fd_, buf, sizeof buf)) > 0)
      output_.append(buf, static_cast<size_t>(n));
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  int status_ = 0;
  bool exited_ = false;
  std::string output_;
};
}  // namespace

TEST(ProjectorNodelet, PublishesLatchedPatternAndCameraInfo)
{
  // Subscribing late still gets the (latched) messages.
  const auto image = waitFor<sensor_msgs::Image>("pattern", 60.0);
  ASSERT_TRUE(image) << "no pattern";
  EXPECT_EQ(image->encoding, "mono8");
  EXPECT_EQ(image->width, 480u);
  EXPECT_EQ(image->height, 320u);
  EXPECT_EQ(image->step, 480u);
  EXPECT_EQ(image->data.size(), 480u * 320u);
  EXPECT_EQ(image->header.frame_id, "projector_optical_frame");
  size_t lit = 0;
  for (uint8_t v : image->data)
    lit += v == 255;
  EXPECT_EQ(lit, 16u * 64u * 33u);

  const auto info = waitFor<sensor_msgs::CameraInfo>("camera_info", 30.0);
  ASSERT_TRUE(info) << "no camera_info";
  EXPECT_EQ(info->width, 480u);
  EXPECT_EQ(info->height, 320u);
  // From the default rig file (see projector.test).
  EXPECT_DOUBLE_EQ(info->K[0], 753.0);
  EXPECT_DOUBLE_EQ(info->K[4], 781.0);
  EXPECT_DOUBLE_EQ(info->K[2], 203.0);
  EXPECT_DOUBLE_EQ(info->K[5], -38.0);
  ASSERT_EQ(info->D.size(), 5u);
  EXPECT_DOUBLE_EQ(info->D[0], 0.02);
  EXPECT_EQ(info->header.frame_id, "projector_optical_frame");
}

TEST(ProjectorNode, InvalidParameterFailsNamingIt)
{
  std::string out;
  const int status = run("rosrun sl_projector projector_node __name:=bad_projector _columns:=100", out);
  EXPECT_NE(status, 0) << out;
  EXPECT_NE(out.find("~columns"), std::string::npos) << out;

  out.clear();
  const int status3 =
      run("rosrun sl_projector projector_node __name:=bad_projector3 _calibration_file:=/no/such.yaml", out);
  EXPECT_NE(status3, 0) << out;
  EXPECT_NE(out.find("~calibration_file: /no/such.yaml: cannot open"), std::string::npos) << out;

  out.clear();
  const int status2 = run("rosrun sl_projector projector_node __name:=bad_projector2 _fx:=-3.0", out);
  EXPECT_NE(status2, 0) << out;
  EXPECT_NE(out.find("~fx"), std::string::npos) << out;
}

TEST(ProjectorNode, MissingDisplayAndBusAreReportedNotFatal)
{
  // The node reports both and carries on: after the reports its (latched) pattern still comes and it
  // is still running until it is told to stop. Nothing here depends on how long it ran.
  Child node({ "rosrun", "sl_projector", "projector_node", "__name:=no_display_projector", "_show_window:=true",
               "_display:=unix:87", "_dlp_setup:=true", "_i2c_bus:=/dev/i2c-none", "pattern:=pattern_no_display",
               "camera_info:=info_no_display" });
  ASSERT_TRUE(node.readUntil({ "cannot open X display 'unix:87'", "/dev/i2c-none" }, 60.0)) << node.output();
  EXPECT_TRUE(waitFor<sensor_msgs::Image>("pattern_no_display", 60.0)) << "no pattern after the reports";
  EXPECT_TRUE(node.running()) << node.output();
  EXPECT_EQ(node.interrupt(), 0) << "exit status after SIGINT\n" << node.output();
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "projector_rostest");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
