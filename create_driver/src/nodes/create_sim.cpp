// Runs the create_driver/sim nodelet (simulated Create on a pty) in its own process.
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "create_sim", "create_driver/sim");
}
