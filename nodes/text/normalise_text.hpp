// The canonical form the table encoder looks labels up by: lower case, runs of whitespace
// collapsed to one space, no leading or trailing space.
#pragma once

#include <string>

namespace gslift {

std::string normalise_text(const std::string& text);

}  // namespace gslift
