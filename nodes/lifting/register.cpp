#include "nodes/lifting/register.hpp"

#include "nodes/lifting/lifting_nodes.hpp"

namespace gslift {

void register_lifting_nodes(Registry& registry) {
  add_lifting_nodes(registry);
}

}  // namespace gslift
