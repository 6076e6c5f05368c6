// Fuzz target: create_driver's SimRobot (the simulated Create behind create_sim) fed arbitrary
// command bytes, with its sensors and clock driven by the input too.
//
// Input: [flags] then operations, each a control byte c:
//   c < 0x80          the next (c & 0x7F) + 1 bytes go to the robot as commands
//   0x80 <= c < 0xC0  step ((c & 0x3F) + 1) * 10 ms
//   c >= 0xC0         then one argument byte v; by c & 0x0F: 0 contact, 1 cliffs, 2 wheel drops,
//                     3 buttons, 4 inject v % 8 + 1 bytes into the next frame, 5 inject them now,
//                     6 power cycle, 7 move the robot, 8 read the sensor state, 9 step v * 10 ms,
//                     10 step an odd dt (0, negative, NaN, infinity, 1e9 s)
//   flags bit 0: Create 2; bit 1: wheels accelerate gradually; bit 2: slip and odometry noise;
//   bit 3: no stall on contact.
// Run time is bounded: at most kMaxSimSeconds of simulated time per input (step() splits time
// into 5 ms steps). Besides the sanitizers it checks that the bytes handed out add up to
// bytesSent() and that the robot's stream, fed to the driver's parser, never overflows it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "create_driver/sim_robot.h"
#include "create_driver/stream_parser.h"
#include "fuzz_input.h"

namespace
{
constexpr double kMaxSimSeconds = 30.0;
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
  using create_driver::Model;
  sl_fuzz::FuzzInput in(data, size);
  const uint8_t flags = in.u8();
  create_driver::SimParams params;
  params.model = (flags & 1) ? Model::CREATE_2 : Model::CREATE_1;
  if (flags & 2)
    params.max_wheel_accel = 1.0;
  if (flags & 4)
  {
    params.slip_left = 0.02;
    params.slip_noise = 0.01;
    params.odom_noise = 0.01;
  }
  params.block_on_contact = (flags & 8) == 0;
  create_driver::SimRobot robot(params);
  create_driver::StreamParser parser(params.model);

  double sim_time = 0.0;
  uint64_t taken = 0;
  create_driver::Bytes out;
  auto step = [&](double dt)
  {
    // An odd dt is passed on as it is (the robot must cope); the budget counts what it may cost.
    const double cost = std::isfinite(dt) ? std::min(std::max(dt, 0.0), 1.0) : 1.0;
    if (sim_time + cost > kMaxSimSeconds)
      return;
    sim_time += cost;
    robot.step(dt);
  };
  while (!in.empty())
  {
    const uint8_t c = in.u8();
    if (c < 0x80)
    {
      const std::vector<uint8_t> cmd = in.bytes((c & 0x7F) + 1u);
      robot.receive(cmd.data(), cmd.size());
    }
    else if (c < 0xC0)
    {
      step(((c & 0x3F) + 1) * 0.010);
    }
    else
    {
      const uint8_t v = in.u8();
      switch (c & 0x0F)
      {
        case 0:
          robot.setContact(v);
          break;
        case 1:
          robot.setCliffs(v);
          break;
        case 2:
          robot.setWheelDrops(v);
          break;
        case 3:
          robot.setButtons(v);
          break;
        case 4:
          robot.injectIntoNextFrame(in.bytes(v % 8 + 1u));
          break;
        case 5:
          robot.injectNow(in.bytes(v % 8 + 1u));
          break;
        case 6:
          robot.powerCycle();
          break;
        case 7:
        {
          create_driver::Pose2D pose;
          pose.x = (v & 0x0F) * 0.5;
          pose.yaw = (v >> 4) * 0.4;
          robot.setPose(pose);
          break;
        }
        case 8:
          (void)robot.sensorState();
          break;
        case 9:
          step(v * 0.010);
          break;
        case 10:
        {
          const double odd[] = {
            0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(), 1e9, 1e-13
          };
          step(odd[v % 6]);
          break;
        }
        default:
          break;
      }
    }
    out.clear();
    robot.takeOutput(out);
    taken += out.size();
    parser.feed(out.data(), out.size());
    FUZZ_CHECK(parser.buffered() <= 258);  // one candidate frame at most: [19][n][n bytes][checksum]
  }
  FUZZ_CHECK(taken == robot.bytesSent());
  FUZZ_CHECK(robot.refusedCommands() <= robot.commands());
  FUZZ_CHECK(std::isfinite(robot.truePose().x) && std::isfinite(robot.truePose().y) &&
             std::isfinite(robot.truePose().yaw));
  return 0;
}
