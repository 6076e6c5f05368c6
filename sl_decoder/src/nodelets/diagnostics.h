// The decoder's diagnostics, filled from the core's counters.
#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>

#include "sl_decoder/decoder_stats.h"

namespace sl_decoder
{
/// The "decoding" status: summary, counts, the last frame's figures and its ray outcomes.
void fillDiagnostics(const DecoderStats& stats, diagnostic_updater::DiagnosticStatusWrapper& status);
}  // namespace sl_decoder
