// Runs the sl_camera/camera nodelet in its own process.
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "camera", "sl_camera/camera");
}
