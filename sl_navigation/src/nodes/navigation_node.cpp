// Runs the sl_navigation/navigation nodelet in its own process (nothing else).
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "navigation", "sl_navigation/navigation");
}
