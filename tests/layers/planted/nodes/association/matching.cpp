// Planted: a family including another family; the adapter file may include the runtime.
#include "nodes/boxes/cluster_boxes.hpp"
