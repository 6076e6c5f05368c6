#pragma once
// The simulator's true rigs, read once: the decoder and calibration tests render with them (the
// calibration tests measure the calibrated rig against them). trueRig():
// sl_evaluation::defaultRigFile() (projector right of the camera); leftRig(): test/rigs/left_rig.yaml
// (the same rig with the projector mirrored to the left).
#include <string>

#include "sl_evaluation/evaluation.h"

inline const sl_projector::Rig& trueRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  return rig;
}

inline const sl_projector::Rig& leftRig()
{
  static const sl_projector::Rig rig =
      sl_projector::loadRig(std::string(SL_EVALUATION_TEST_DIR) + "/rigs/left_rig.yaml");
  return rig;
}
