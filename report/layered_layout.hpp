// A layered drawing of a directed acyclic graph (the Sugiyama scheme: Sugiyama, Tagawa & Toda 1981,
// "Methods for visual understanding of hierarchical system structures"), in its simplest form:
// 1. layers: each node one layer past its deepest predecessor (longest path);
// 2. an edge that skips layers gets a thin dummy node on each layer it crosses, so that it is
//    routed around the boxes in its own lane instead of through them;
// 3. order inside each layer: barycenter sweeps down and up, keeping the order with the fewest
//    crossings seen;
// 4. x positions: each item pulled to the mean centre of its neighbours, then pushed right just
//    enough to keep the order and the gaps, and the layer shifted back to its mean pull.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

namespace gslift::report {

struct LayeredLayout {
  std::vector<int> layer;  // per node
  std::vector<double> x;   // per node: its left edge (the leftmost item is at 0)
  // Per edge: the x of its lane on each layer strictly between its ends (empty when the edge
  // joins neighbouring layers).
  std::vector<std::vector<double>> route;
  // Per layer: its items in order, nodes as their index and dummies as -1 - (edge index).
  std::vector<std::vector<int>> order;
  double width = 0;      // right edge of the rightmost item
  size_t crossings = 0;  // edge segments crossing between neighbouring layers, after ordering
};

// `widths`: each node's box width; `edges`: (from, to) node indices; `gap`: the space between
// neighbouring items (half of it beside a dummy, whose own width is `gap` / 2). A cycle (which a
// valid graph never has) does not hang the layout: its nodes are put after every other node.
LayeredLayout layered_layout(const std::vector<double>& widths,
                             const std::vector<std::pair<int, int>>& edges, double gap);

}  // namespace gslift::report
