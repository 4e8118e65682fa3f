#include "nodes/scene/prompts.hpp"

namespace gslift {

const EnumNames<PromptKind>& prompt_kind_names() {
  static const EnumNames<PromptKind> names = {{PromptKind::Point, "point"},
                                              {PromptKind::Scribble, "scribble"},
                                              {PromptKind::Mask, "mask"},
                                              {PromptKind::Sam, "sam"}};
  return names;
}

}  // namespace gslift
