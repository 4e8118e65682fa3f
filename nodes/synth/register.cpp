#include "nodes/synth/register.hpp"

#include <locale>
#include <sstream>

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/synth/embedded_capture.hpp"

namespace gslift {

namespace {

using synth::KnobInfo;
using synth::SynthKnobs;

std::string exact_text(double v) {
  std::ostringstream s;
  s.imbue(std::locale::classic());
  s.precision(17);
  s << v;
  return s.str();
}

// One ParamSpec per knob, from the knob table (defaults = the default preset; a preset param
// changes the values the node starts from, explicit params override them).
std::vector<ParamSpec> knob_params() {
  const SynthKnobs d;
  std::vector<ParamSpec> params;
  for (const KnobInfo& k : synth::synth_knob_table()) {
    const std::string doc = k.doc + " (the preset's value unless set)";
    if (auto f = std::get_if<bool SynthKnobs::*>(&k.field)) {
      params.push_back(bool_param(k.name, d.*(*f), doc));
    } else if (auto f = std::get_if<int SynthKnobs::*>(&k.field)) {
      params.push_back(int_param(k.name, d.*(*f), doc, k.min, k.max));
    } else {
      params.push_back(
          float_param(k.name, d.*std::get<double SynthKnobs::*>(k.field), doc, k.min, k.max));
    }
  }
  return params;
}

void add_synth_capture(Registry& registry) {
  const synth::OrSceneOptions d;
  std::vector<ParamSpec> params = {
      int_param("seed", 0, "layout seed of the embedded operating room", 0),
      string_param("phase", synth::to_string(d.phase), "phase of the operation",
                   {"preparation", "surgery", "closing"}),
      int_param("views", d.views, "ceiling-corner cameras (one in five is held out)", 4, 8),
      int_param("width", d.width, "image width in pixels", 16, 8192),
      int_param("height", d.height, "image height in pixels", 16, 8192),
      string_param("preset", "default", "failure rates of the simulated VLM/SAM/MVS models",
                   synth::preset_names()),
  };
  const std::vector<ParamSpec> knobs = knob_params();
  params.insert(params.end(), knobs.begin(), knobs.end());
  NodeSpec spec{"synth.capture",
                "generate the embedded operating-room capture (cached by its settings) and open "
                "it like ingest.capture",
                {},
                {{"capture", PortTypeName<Capture>::value,
                  "posed views, depth prior, sparse points, VLM/SAM files and ground truth"}},
                std::move(params)};
  registry.add(std::move(spec), [](NodeContext& ctx) {
    // A knob param left at the default-preset value is not passed on, so that the preset decides
    // it; a value that differs from the default preset was set on purpose and wins.
    const SynthKnobs defaults;
    std::vector<std::pair<std::string, std::string>> entries = {
        {"seed", std::to_string(ctx.param_int("seed"))},
        {"phase", ctx.param_string("phase")},
        {"views", std::to_string(ctx.param_int("views"))},
        {"width", std::to_string(ctx.param_int("width"))},
        {"height", std::to_string(ctx.param_int("height"))},
        {"preset", ctx.param_string("preset")},
    };
    for (const KnobInfo& k : synth::synth_knob_table()) {
      std::string value;
      if (std::holds_alternative<bool SynthKnobs::*>(k.field)) {
        value = ctx.param_bool(k.name) ? "true" : "false";
      } else if (std::holds_alternative<int SynthKnobs::*>(k.field)) {
        value = std::to_string(ctx.param_int(k.name));
      } else {
        value = exact_text(ctx.param_float(k.name));
      }
      SynthKnobs probe = defaults;
      synth::set_knob(probe, k.name, value);
      if (synth::knob_value(probe, k) != synth::knob_value(defaults, k)) {
        entries.emplace_back(k.name, value);
      }
    }
    const synth::OrCaptureSettings settings = synth::make_settings(entries);
    const auto folder = synth::ensure_cached_capture(settings);
    Capture capture = load_capture(folder);
    ctx.record("cache_folder", folder.string());
    ctx.record("views", static_cast<double>(capture.views.size()));
    ctx.output("capture", std::move(capture));
  });
}

}  // namespace

void register_synth_nodes(Registry& registry) {
  add_synth_capture(registry);
  register_capture_provider("embedded", [](const std::string& spec) {
    return synth::ensure_cached_capture(synth::parse_embedded_spec(spec));
  });
}

}  // namespace gslift
