#pragma once
// Error reporting for the high-level layers (ingest, archive, pipeline): ridge::Error and
// ridge::Cancelled, defined in the public <ridge/error.h>.
//
// Hot or fuzzed code (codecs, block parsing) returns error codes instead; the layers above
// turn those into an Error whose message names the file and the problem, which the command
// line prints verbatim before exiting non-zero.
#include "ridge/error.h"
