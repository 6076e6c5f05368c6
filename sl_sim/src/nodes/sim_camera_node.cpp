// Runs the sl_sim/sim_camera nodelet in its own process.
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "sim_camera", "sl_sim/sim_camera");
}
