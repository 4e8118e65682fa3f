#include "report/layered_layout.hpp"

#include <algorithm>
#include <numeric>

namespace gslift::report {

namespace {

// Kahn's algorithm, then longest-path layers.
std::vector<int> longest_path_layers(size_t n, const std::vector<std::pair<int, int>>& edges) {
  std::vector<std::vector<int>> succ(n);
  std::vector<int> indegree(n, 0);
  for (const auto& [a, b] : edges) {
    succ[a].push_back(b);
    ++indegree[b];
  }
  std::vector<int> layer(n, 0), order;
  for (size_t i = 0; i < n; ++i)
    if (indegree[i] == 0) order.push_back(int(i));
  for (size_t k = 0; k < order.size(); ++k)
    for (int s : succ[order[k]]) {
      layer[s] = std::max(layer[s], layer[order[k]] + 1);
      if (--indegree[s] == 0) order.push_back(s);
    }
  if (order.size() < n) {  // a cycle: its nodes go below everything else
    const int last = *std::max_element(layer.begin(), layer.end()) + 1;
    for (size_t i = 0; i < n; ++i)
      if (indegree[i] > 0) layer[i] = last;
  }
  return layer;
}

// The proper graph: nodes and dummies (items), with edges only between neighbouring layers.
struct Proper {
  std::vector<int> layer;                  // per item
  std::vector<double> width;               // per item
  std::vector<std::vector<int>> up, down;  // neighbours in the layer above / below
  std::vector<std::vector<int>> dummies;   // per edge: its dummy items, top to bottom
};

Proper make_proper(const std::vector<double>& widths, const std::vector<int>& layer,
                   const std::vector<std::pair<int, int>>& edges, double gap) {
  Proper p;
  p.layer = layer;
  p.width = widths;
  const auto add_item = [&](int l, double w) {
    p.layer.push_back(l);
    p.width.push_back(w);
    return int(p.layer.size()) - 1;
  };
  p.dummies.resize(edges.size());
  std::vector<std::pair<int, int>> links;
  for (size_t e = 0; e < edges.size(); ++e) {
    auto [a, b] = edges[e];
    if (layer[b] <= layer[a]) continue;  // only a cycle does this; the edge is drawn directly
    int prev = a;
    for (int l = layer[a] + 1; l < layer[b]; ++l) {
      const int d = add_item(l, gap / 2);
      p.dummies[e].push_back(d);
      links.push_back({prev, d});
      prev = d;
    }
    links.push_back({prev, b});
  }
  p.up.resize(p.layer.size());
  p.down.resize(p.layer.size());
  for (const auto& [a, b] : links) p.down[a].push_back(b), p.up[b].push_back(a);
  return p;
}

size_t count_crossings(const Proper& p, const std::vector<std::vector<int>>& order) {
  std::vector<int> pos(p.layer.size());
  for (const auto& items : order)
    for (size_t k = 0; k < items.size(); ++k) pos[items[k]] = int(k);
  size_t count = 0;
  for (const auto& items : order) {
    std::vector<std::pair<int, int>> segs;  // (top position, bottom position)
    for (int a : items)
      for (int b : p.down[a]) segs.push_back({pos[a], pos[b]});
    for (size_t i = 0; i < segs.size(); ++i)
      for (size_t j = i + 1; j < segs.size(); ++j)
        count += (segs[i].first < segs[j].first && segs[i].second > segs[j].second) ||
                 (segs[i].first > segs[j].first && segs[i].second < segs[j].second);
  }
  return count;
}

// Orders `items` by the mean position of their `neighbours` (an item without any keeps its
// place); stable, so ties keep their order.
void barycenter_order(std::vector<int>& items, const std::vector<std::vector<int>>& neighbours,
                      const std::vector<int>& pos) {
  std::vector<double> key(items.size());
  for (size_t k = 0; k < items.size(); ++k) {
    double sum = 0;
    for (int m : neighbours[items[k]]) sum += pos[m];
    key[k] = neighbours[items[k]].empty() ? double(k) : sum / double(neighbours[items[k]].size());
  }
  std::vector<size_t> idx(items.size());
  std::iota(idx.begin(), idx.end(), 0);
  std::stable_sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return key[a] < key[b]; });
  std::vector<int> sorted;
  for (size_t i : idx) sorted.push_back(items[i]);
  items = sorted;
}

std::vector<std::vector<int>> order_layers(const Proper& p, int layer_count) {
  std::vector<std::vector<int>> order(layer_count);
  for (size_t i = 0; i < p.layer.size(); ++i) order[p.layer[i]].push_back(int(i));
  std::vector<int> pos(p.layer.size());
  const auto renumber = [&] {
    for (const auto& items : order)
      for (size_t k = 0; k < items.size(); ++k) pos[items[k]] = int(k);
  };
  renumber();
  auto best = order;
  size_t best_crossings = count_crossings(p, order);
  for (int round = 0; round < 8 && best_crossings > 0; ++round) {
    for (int l = 1; l < layer_count; ++l) barycenter_order(order[l], p.up, pos), renumber();
    for (int l = layer_count - 2; l >= 0; --l) barycenter_order(order[l], p.down, pos), renumber();
    const size_t c = count_crossings(p, order);
    if (c < best_crossings) best = order, best_crossings = c;
  }
  return best;
}

// Left edges: pulled towards the neighbours' centres, kept in order with their gaps.
std::vector<double> place(const Proper& p, const std::vector<std::vector<int>>& order, double gap) {
  std::vector<double> x(p.layer.size(), 0);
  const size_t node_count = p.layer.size() - [&] {
    size_t d = 0;
    for (const auto& e : p.dummies) d += e.size();
    return d;
  }();
  const auto spacing = [&](int a, int b) {
    return size_t(a) < node_count && size_t(b) < node_count ? gap : gap / 2;
  };
  const auto pack = [&](const std::vector<int>& items, const std::vector<double>& want) {
    // Forward pass keeps order and gaps; then the layer shifts back by its mean displacement.
    double shift = 0;
    for (size_t k = 0; k < items.size(); ++k) {
      const int i = items[k];
      x[i] = want[k];
      if (k)
        x[i] = std::max(x[i], x[items[k - 1]] + p.width[items[k - 1]] + spacing(items[k - 1], i));
      shift += want[k] - x[i];
    }
    shift /= double(std::max<size_t>(1, items.size()));
    for (int i : items) x[i] += shift;
  };
  for (const auto& items : order) pack(items, std::vector<double>(items.size(), 0));
  const auto centre = [&](int i) { return x[i] + p.width[i] / 2; };
  for (int round = 0; round < 6; ++round)
    for (int pass = 0; pass < 2; ++pass) {
      const auto& neighbours = pass == 0 ? p.up : p.down;
      const int n = int(order.size());
      for (int s = 0; s < n; ++s) {
        const auto& items = order[pass == 0 ? s : n - 1 - s];
        std::vector<double> want;
        for (int i : items) {
          if (neighbours[i].empty()) {
            want.push_back(x[i]);
            continue;
          }
          double sum = 0;
          for (int m : neighbours[i]) sum += centre(m);
          want.push_back(sum / double(neighbours[i].size()) - p.width[i] / 2);
        }
        pack(items, want);
      }
    }
  const double left = x.empty() ? 0 : *std::min_element(x.begin(), x.end());
  for (double& v : x) v -= left;
  return x;
}

}  // namespace

LayeredLayout layered_layout(const std::vector<double>& widths,
                             const std::vector<std::pair<int, int>>& edges, double gap) {
  const size_t n = widths.size();
  LayeredLayout l;
  l.layer = longest_path_layers(n, edges);
  const int layer_count = n ? *std::max_element(l.layer.begin(), l.layer.end()) + 1 : 0;
  const Proper p = make_proper(widths, l.layer, edges, gap);
  const auto order = order_layers(p, layer_count);
  l.crossings = count_crossings(p, order);
  const std::vector<double> x = place(p, order, gap);
  l.x.assign(x.begin(), x.begin() + long(n));
  for (size_t i = 0; i < x.size(); ++i) l.width = std::max(l.width, x[i] + p.width[i]);
  l.route.resize(edges.size());
  std::vector<int> edge_of(p.layer.size(), -1);
  for (size_t e = 0; e < edges.size(); ++e)
    for (int d : p.dummies[e]) {
      l.route[e].push_back(x[d] + p.width[d] / 2);
      edge_of[d] = int(e);
    }
  for (const auto& items : order) {
    l.order.emplace_back();
    for (int i : items) l.order.back().push_back(size_t(i) < n ? i : -1 - edge_of[i]);
  }
  return l;
}

}  // namespace gslift::report
