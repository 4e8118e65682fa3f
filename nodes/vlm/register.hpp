#pragma once

#include <functional>
#include <memory>

#include "nodes/scene/text_encoder.hpp"
#include "nodes/scene/vocabulary.hpp"
#include "runtime/registry.hpp"

namespace gslift {

// The encoder that maps a reply's free labels onto the prompt's vocabulary when vlm.query's
// `encoder` port is unwired. The catalogue (nodes/builtin.cpp) passes the text family's lexical
// encoder, so that this family does not depend on another one.
using UnwiredLabelEncoder =
    std::function<std::shared_ptr<const TextEncoder>(const Vocabulary& vocabulary)>;

// vlm.query: the live multi-round VLM perceptor (docs/vlm_query.md).
void register_vlm_nodes(Registry& registry, UnwiredLabelEncoder unwired_encoder);

}  // namespace gslift
