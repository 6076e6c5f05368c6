#pragma once
// The rig the tests calibrate against: sl_projector's default rig file, read once.
#include "sl_rig/rig.h"

inline const sl_projector::Rig& trueRig()
{
  static const sl_projector::Rig rig = sl_projector::loadRig(SL_PROJECTOR_CONFIG_DIR "/default_rig.yaml");
  return rig;
}
