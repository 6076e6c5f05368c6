#include "diagnostics.h"

#include <string>

namespace sl_decoder
{
void fillDiagnostics(const DecoderStats& s, diagnostic_updater::DiagnosticStatusWrapper& status)
{
  using diagnostic_msgs::DiagnosticStatus;
  status.summary(s.level() == DecoderStats::Level::Warn ? DiagnosticStatus::WARN : DiagnosticStatus::OK, s.summary());
  status.add("frames", s.frames);
  status.add("blobs", s.last_blobs);
  status.add("decoded", s.last_decoded);
  status.add("valid points", s.last_valid);
  status.add("valid fraction of blobs", s.validFraction());
  status.add("processing time (ms)", s.last_ms);
  status.add("rejected images", s.rejected);
  status.add("tf failures", s.tf_failures);
  status.add("tf newest used (not yet at the image time)", s.tf_latest);
  status.add("tf age of the newest used, s", s.tf_age);
  for (int k = 1; k < kRayStates; ++k)  // the ray outcomes of the last classified frame
    status.add(std::string("rays ") + toString(static_cast<RayState>(k)), s.last_rays[static_cast<size_t>(k)]);
}
}  // namespace sl_decoder
