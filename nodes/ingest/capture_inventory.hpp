// What a capture holds for the preflight (runtime/preflight.hpp): per CaptureItem whether it is
// there, where it was looked for and what produces it. Reads the capture's folder listing and
// capture.yaml only, never an image, so the check stays well under a second on any capture.
#pragma once

#include "nodes/scene/capture.hpp"
#include "param/capture_need.hpp"

namespace gslift {

CaptureInventory capture_inventory(const Capture& capture);

}  // namespace gslift
