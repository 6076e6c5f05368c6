// Runs the sl_evaluation/bump_baseline nodelet in its own process (nothing else).
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "bump_baseline", "sl_evaluation/bump_baseline");
}
