#include "nodes/ingest/register.hpp"

namespace gslift {

void register_ingest_nodes(Registry& /*registry*/) {}

}  // namespace gslift
