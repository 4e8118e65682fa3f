// Wall-clock timestamps for records (run.json, batch markers).
#pragma once

#include <string>

namespace gslift {

// The current time as ISO 8601 UTC with second precision: "2026-11-22T07:30:00Z".
std::string utc_now_iso8601();

}  // namespace gslift
