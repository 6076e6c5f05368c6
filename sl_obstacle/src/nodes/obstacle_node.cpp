// Runs the sl_obstacle/obstacle nodelet in its own process (nothing else).
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "obstacle", "sl_obstacle/obstacle");
}
