#include "nodes/boxes/register.hpp"

namespace gslift {

void register_boxes_nodes(Registry& /*registry*/) {}

}  // namespace gslift
