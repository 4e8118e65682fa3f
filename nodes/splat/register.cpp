#include "nodes/splat/register.hpp"

namespace gslift {

void register_splat_nodes(Registry& /*registry*/) {}

}  // namespace gslift
