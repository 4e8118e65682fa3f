// Planted: base/ reaching up into graph/.
#include "graph/param_table.hpp"
