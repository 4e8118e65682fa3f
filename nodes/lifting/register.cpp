#include "nodes/lifting/register.hpp"

namespace gslift {

void register_lifting_nodes(Registry& /*registry*/) {}

}  // namespace gslift
