#include "nodes/synth/register.hpp"

#include "nodes/ingest/capture_loader.hpp"
#include "nodes/ingest/capture_provider.hpp"
#include "nodes/synth/embedded_capture.hpp"

namespace gslift {

namespace {

using synth::SynthKnobs;

// synth.capture's params: the scene, the preset, and every knob (defaults = the default preset).
struct SynthCaptureParams {
  synth::OrSceneOptions scene;
  synth::SynthPreset preset = synth::SynthPreset::Default;
  SynthKnobs knobs;
};

const ParamTable<synth::OrSceneOptions>& scene_param_table() {
  using O = synth::OrSceneOptions;
  static const ParamTable<O> table =
      ParamTable<O>()
          .add("seed", &O::seed, "layout seed of the embedded operating room", 0)
          .add("phase", &O::phase, synth::or_phase_names(), "phase of the operation")
          .add("views", &O::views, "ceiling-corner cameras (one in five is held out)", 4, 8)
          .add("width", &O::width, "image width in pixels", 16, 8192)
          .add("height", &O::height, "image height in pixels", 16, 8192);
  return table;
}

const ParamTable<SynthCaptureParams>& synth_capture_param_table() {
  using P = SynthCaptureParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .nest(&P::scene, scene_param_table())
          .add("preset", &P::preset, synth::preset_names(),
               "failure rates of the simulated VLM/SAM/MVS models")
          .nest(&P::knobs, synth::synth_knob_table(), " (the preset's value unless set)");
  return table;
}

void run_synth_capture(NodeContext& ctx, const SynthCaptureParams& p) {
  synth::OrCaptureSettings settings;
  settings.scene = p.scene;
  settings.preset = p.preset;
  settings.knobs = synth::preset_knobs(p.preset);
  // A knob left at its default-preset value lets the preset decide; a value that differs from
  // the default preset was set on purpose and wins.
  const SynthKnobs defaults;
  for (const synth::KnobField& k : synth::synth_knob_table().fields())
    if (k.get(p.knobs) != k.get(defaults)) k.set(settings.knobs, k.get(p.knobs));
  const auto folder = synth::ensure_cached_capture(settings);
  Capture capture = load_capture(folder);
  ctx.record("cache_folder", folder.string());
  ctx.record("views", static_cast<double>(capture.views.size()));
  ctx.output("capture", std::move(capture));
}

void add_synth_capture(Registry& registry) {
  NodeSpec spec{"synth.capture",
                "generate the embedded operating-room capture (cached by its settings) and open "
                "it like ingest.capture",
                {},
                {{"capture", PortTypeName<Capture>::value,
                  "posed views, depth prior, sparse points, VLM/SAM files and ground truth"}}};
  registry.add(std::move(spec), synth_capture_param_table(), run_synth_capture);
}

}  // namespace

void register_synth_nodes(Registry& registry) {
  add_synth_capture(registry);
  register_capture_provider("embedded", [](const std::string& spec) {
    return synth::ensure_cached_capture(synth::parse_embedded_spec(spec));
  });
}

}  // namespace gslift
