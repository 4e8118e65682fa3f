#include "nodes/synth/register.hpp"

namespace gslift {

void register_synth_nodes(Registry& /*registry*/) {}

}  // namespace gslift
