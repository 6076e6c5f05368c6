// Runs the create_driver/driver nodelet in its own process (nothing else).
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "create_driver", "create_driver/driver");
}
