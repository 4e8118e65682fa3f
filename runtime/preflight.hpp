// The check before a run: every node's capture needs (PortSpec::needs, declared beside its
// ports) against what the capture it reads holds (the opening node's Registry::CaptureProbe).
// It reads no image, so a graph that would fail late (LangOR on a capture without VLM replies:
// minutes of reconstruction, then no masks) is refused in well under a second, with one
// message per missing thing.
#pragma once

#include <string>
#include <vector>

#include "graph/graph.hpp"
#include "runtime/registry.hpp"

namespace gslift {

// One message per missing thing, in graph order: "<yaml>:<line>:<col>: node 'vlm' (ingest.vlm)
// needs VLM grounding replies: looked for <where>; <what produces it>". A capture that cannot be
// opened is one message naming the node that opens it. A need is traced to the node that
// produced the Capture wired to the port; a capture made in the graph (synth.capture) has no
// probe and is not checked. Empty when everything is there.
std::vector<std::string> preflight_problems(const Graph& graph, const Registry& registry);

// Throws InputError listing every problem, one per line, when there is any.
void check_preflight(const Graph& graph, const Registry& registry);

}  // namespace gslift
