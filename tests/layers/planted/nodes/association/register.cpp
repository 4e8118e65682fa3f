// Planted: an adapter including the runtime (allowed).
#include "runtime/registry.hpp"
