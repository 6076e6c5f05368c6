// Runs the sl_calibration/calibration nodelet in its own process (with a multi-threaded spinner, so a
// capture service can wait for images).
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "calibration", "sl_calibration/calibration");
}
