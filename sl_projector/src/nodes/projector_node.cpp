// Runs the sl_projector/projector nodelet in its own process.
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "projector", "sl_projector/projector");
}
