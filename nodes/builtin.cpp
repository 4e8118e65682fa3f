#include "nodes/builtin.hpp"

#include <memory>

#include "nodes/association/register.hpp"
#include "nodes/boxes/register.hpp"
#include "nodes/eval/register.hpp"
#include "nodes/features/register.hpp"
#include "nodes/fusion/register.hpp"
#include "nodes/inference/register.hpp"
#include "nodes/ingest/register.hpp"
#include "nodes/lifting/register.hpp"
#include "nodes/masks/register.hpp"
#include "nodes/scene/port_archive.hpp"
#include "nodes/splat/register.hpp"
#include "nodes/synth/register.hpp"
#include "nodes/text/lexical_text_encoder.hpp"
#include "nodes/text/register.hpp"
#include "nodes/vlm/register.hpp"

namespace gslift {

namespace {

// Every port type with a binary form (nodes/scene/port_archive.hpp); the stage cache stands in
// for the nodes whose outputs all have one.
void register_port_codecs(Registry& registry) {
  registry.add_codec<BoxSet>(kPortArchiveVersion);
  registry.add_codec<GaussianModel>(kPortArchiveVersion);
  registry.add_codec<InstanceSet>(kPortArchiveVersion);
  registry.add_codec<LabelMapSet>(kPortArchiveVersion);
  registry.add_codec<ViewClassifiers>(kPortArchiveVersion);
  registry.add_codec<LabelClassifier>(kPortArchiveVersion);
  registry.add_codec<LiftedInstances>(kPortArchiveVersion);
  registry.add_codec<MaskSet>(kPortArchiveVersion);
  registry.add_codec<PromptSet>(kPortArchiveVersion);
  registry.add_codec<SemanticMaps>(kPortArchiveVersion);
  registry.add_codec<TextQueryResults>(kPortArchiveVersion);
  registry.add_codec<Vocabulary>(kPortArchiveVersion);
  registry.add_codec<ViewPoses>(kPortArchiveVersion);
}

}  // namespace

void register_builtin_nodes(Registry& registry) {
  register_port_codecs(registry);
  register_ingest_nodes(registry);
  register_synth_nodes(registry);
  register_splat_nodes(registry);
  register_boxes_nodes(registry);
  register_lifting_nodes(registry);
  register_text_nodes(registry);
  register_association_nodes(registry);
  register_inference_nodes(registry);
  register_eval_nodes(registry);
  register_features_nodes(registry);
  // vlm.query maps free labels with the text family's offline encoder when none is wired.
  register_vlm_nodes(registry, [](const Vocabulary& vocabulary) {
    return std::make_shared<const LexicalTextEncoder>(vocabulary);
  });
  register_masks_nodes(registry);
  register_fusion_nodes(registry);
}

}  // namespace gslift
