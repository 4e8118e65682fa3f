// Planted: base/ reaching up into graph/.
#include "graph/graph.hpp"
