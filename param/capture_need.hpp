// What a node reads from its capture besides the posed views: declared on the node's Capture
// input port (PortSpec::needs), so that a run can be refused before any node runs when the
// capture lacks it (runtime/preflight.hpp), instead of failing or returning nothing hours later.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace gslift {

// The parts of a capture a node may need (docs/capture_format.md names their files).
enum class CaptureItem {
  Images,        // every view's colour image
  Depth,         // a depth prior for every view
  VlmReplies,    // VLM grounding replies, vlm/<view>/round_<k>.txt
  SamAutoMasks,  // SAM automatic masks, sam_auto/<view>.json
  GtInstances,   // ground-truth instance maps
  GtSemantics,   // ground-truth class maps
  GtClasses,     // the ground-truth class names (classes.yaml)
  HeldOutViews,  // test views, for held-out answers and metrics
  NamedFolder,   // a folder one of the node's params names (masks.folder's `folder`)
};

// "VLM grounding replies": what the item is, for messages.
const char* capture_item_text(CaptureItem item);

struct CaptureNeed {
  CaptureItem item;
  // The need holds only while the node's param `when_param` has the value `when_value` (its
  // text: "box", "test"); an empty `when_param` = always.
  std::string when_param{};
  std::string when_value{};
  // NamedFolder: the param that names the folder (relative: to the capture's folder first,
  // resolve_in_capture) and what writes it, for the message.
  std::string folder_param{};
  std::string produced_by{};
};

// What a capture holds of one item, as the node that opens it finds it before the run.
struct CaptureItemState {
  bool present = false;
  std::string looked_for;   // the file or folder looked at ("<capture>/vlm/ (<view>/round_0.txt)")
  std::string produced_by;  // what writes it: a node, a graph, or an outside tool and its layout
};

struct CaptureInventory {
  std::filesystem::path root;  // the capture's folder; empty for one built in memory
  std::map<CaptureItem, CaptureItemState> items;

  CaptureItemState& operator[](CaptureItem item) { return items[item]; }
};

// A path a graph gives relative to its capture: `root / path` when that exists, else `path`
// as given (relative to the working directory). Absolute paths are kept.
std::filesystem::path resolve_in_capture(const std::filesystem::path& root,
                                         const std::filesystem::path& path);

}  // namespace gslift
