// Runs the sl_decoder/decoder nodelet in its own process.
#include "sl_params/nodelet_node.h"

int main(int argc, char** argv)
{
  return sl_params::runNodelet(argc, argv, "decoder", "sl_decoder/decoder");
}
