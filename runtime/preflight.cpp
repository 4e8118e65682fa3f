#include "runtime/preflight.hpp"

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>

#include "base/errors.hpp"

namespace gslift {

namespace {

std::string where(const GraphNode& node) {
  return node.loc.file.empty() ? std::string() : node.loc.str() + ": ";
}

std::string describe(const GraphNode& node) {
  return "node '" + node.id + "' (" + node.type + ")";
}

bool need_holds(const CaptureNeed& need, const GraphNode& node) {
  if (need.when_param.empty()) return true;
  auto it = node.params.find(need.when_param);
  if (it == node.params.end()) return false;
  // An enum param's value is its name, unquoted (to_string would quote it).
  if (const auto* text = std::get_if<std::string>(&it->second)) return *text == need.when_value;
  return to_string(it->second) == need.when_value;
}

// The probed inventories of the graph's capture-opening nodes, each probed once; nullopt for a
// capture that could not be opened (its one message is in `problems`).
class Inventories {
 public:
  Inventories(const Registry& registry, std::vector<std::string>& problems)
      : registry_(registry), problems_(problems) {}

  // The inventory of the capture `source` produced, or null when it is not probed (made in the
  // graph) or could not be opened.
  const CaptureInventory* of(const GraphNode& source) {
    const Registry::CaptureProbe* probe = registry_.capture_probe(source.type);
    if (!probe) return nullptr;
    auto it = probed_.find(source.id);
    if (it == probed_.end()) {
      std::optional<CaptureInventory> inventory;
      try {
        inventory = (*probe)(source.params);
      } catch (const InputError& e) {
        problems_.push_back(where(source) + describe(source) +
                            " cannot open its capture: " + e.what());
      }
      it = probed_.emplace(source.id, std::move(inventory)).first;
    }
    return it->second ? &*it->second : nullptr;
  }

 private:
  const Registry& registry_;
  std::vector<std::string>& problems_;
  std::map<std::string, std::optional<CaptureInventory>> probed_;
};

// The problem with a NamedFolder need, or "" when the folder the node's param names is there
// with a file in it. A param given by a variable still unset is left to the loader.
std::string named_folder_problem(const CaptureNeed& need, const GraphNode& node,
                                 const CaptureInventory& inventory) {
  auto it = node.params.find(need.folder_param);
  const auto* text = it == node.params.end() ? nullptr : std::get_if<std::string>(&it->second);
  if (!text || text->empty()) return "";
  const std::filesystem::path folder = resolve_in_capture(inventory.root, *text);
  std::error_code ec;
  if (std::filesystem::is_directory(folder, ec) &&
      std::filesystem::directory_iterator(folder, ec) != std::filesystem::directory_iterator())
    return "";
  std::string looked = (folder / "").string();
  if (std::filesystem::path(*text).is_relative() && !inventory.root.empty() &&
      folder != inventory.root / *text)
    looked = ((inventory.root / *text) / "").string() + " and " + looked;
  return "the folder its param '" + need.folder_param + "' names (" + *text + "): looked for " +
         looked + " (none, or empty); " + need.produced_by;
}

// The node that opened the capture `node` outputs: back through the nodes that hand a capture on
// (an input `capture` and an output of its type: splat.refined_capture replaces the poses), so
// that what a consumer needs is asked of the capture itself.
const GraphNode* capture_opener(const Graph& graph, const Registry& registry,
                                const GraphNode* node) {
  for (size_t hops = 0; node && hops < graph.nodes.size(); ++hops) {
    if (registry.capture_probe(node->type)) return node;
    const NodeSpec* spec = registry.find(node->type);
    const auto in = node->inputs.find("capture");
    if (!spec || in == node->inputs.end()) return node;
    const auto input = std::find_if(spec->inputs.begin(), spec->inputs.end(),
                                    [](const PortSpec& p) { return p.name == "capture"; });
    const bool hands_on = input != spec->inputs.end() &&
                          std::any_of(spec->outputs.begin(), spec->outputs.end(),
                                      [&](const PortSpec& p) { return p.type == input->type; });
    if (!hands_on) return node;
    node = graph.find(in->second.node);
  }
  return node;
}

}  // namespace

std::vector<std::string> preflight_problems(const Graph& graph, const Registry& registry) {
  std::vector<std::string> problems;
  Inventories inventories(registry, problems);
  // Every capture-opening node is probed, also one whose consumers need nothing of it: a
  // capture that is not there is the first thing to say.
  for (const auto& node : graph.nodes) inventories.of(node);
  for (const auto& node : graph.nodes) {
    const NodeSpec* spec = registry.find(node.type);
    if (!spec) continue;
    for (const auto& port : spec->inputs) {
      auto wired = node.inputs.find(port.name);
      if (port.needs.empty() || wired == node.inputs.end()) continue;
      const GraphNode* source = capture_opener(graph, registry, graph.find(wired->second.node));
      const CaptureInventory* inventory = source ? inventories.of(*source) : nullptr;
      if (!inventory) continue;
      for (const auto& need : port.needs) {
        if (!need_holds(need, node)) continue;
        if (need.item == CaptureItem::NamedFolder) {
          const std::string problem = named_folder_problem(need, node, *inventory);
          if (!problem.empty())
            problems.push_back(where(node) + describe(node) + " needs " + problem);
          continue;
        }
        auto state = inventory->items.find(need.item);
        if (state == inventory->items.end() || state->second.present) continue;
        problems.push_back(where(node) + describe(node) + " needs " + capture_item_text(need.item) +
                           " of capture '" + source->id + "': looked for " +
                           state->second.looked_for + "; " + state->second.produced_by);
      }
    }
  }
  return problems;
}

void check_preflight(const Graph& graph, const Registry& registry) {
  const std::vector<std::string> problems = preflight_problems(graph, registry);
  if (problems.empty()) return;
  std::string text = "preflight: " + std::to_string(problems.size()) + " problem" +
                     (problems.size() == 1 ? "" : "s") +
                     " with what the graph needs of its capture; nothing was run:";
  for (const auto& p : problems) text += "\n  " + p;
  throw InputError(text);
}

}  // namespace gslift
