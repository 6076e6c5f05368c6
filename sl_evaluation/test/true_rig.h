#pragma once
// The simulator's true rig (sl_evaluation::defaultRigFile()), read once: the calibration tests render
// with it and measure the calibrated rig against it.
#include "sl_evaluation/evaluation.h"

inline const sl_projector::Rig& trueRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(sl_evaluation::defaultRigFile());
  return rig;
}
