// Planted: an algorithm including the runtime, and one including its own family (allowed).
#include "runtime/node.hpp"
#include "nodes/lifting/hdbscan.hpp"
