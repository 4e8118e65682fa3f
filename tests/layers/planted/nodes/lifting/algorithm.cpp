// Planted: an algorithm including the runtime, and one including its own family (allowed).
#include "nodes/lifting/hdbscan.hpp"
#include "runtime/node.hpp"
