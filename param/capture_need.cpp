#include "param/capture_need.hpp"

namespace gslift {

const char* capture_item_text(CaptureItem item) {
  switch (item) {
    case CaptureItem::Images:
      return "the views' colour images";
    case CaptureItem::Depth:
      return "a depth prior for every view";
    case CaptureItem::VlmReplies:
      return "VLM grounding replies";
    case CaptureItem::SamAutoMasks:
      return "SAM automatic masks";
    case CaptureItem::GtInstances:
      return "ground-truth instance maps";
    case CaptureItem::GtSemantics:
      return "ground-truth class maps";
    case CaptureItem::GtClasses:
      return "ground-truth class names";
    case CaptureItem::HeldOutViews:
      return "held-out (test) views";
    case CaptureItem::NamedFolder:
      return "a folder";
  }
  return "?";
}

std::filesystem::path resolve_in_capture(const std::filesystem::path& root,
                                         const std::filesystem::path& path) {
  if (path.is_relative() && !root.empty() && std::filesystem::exists(root / path))
    return root / path;
  return path;
}

}  // namespace gslift
