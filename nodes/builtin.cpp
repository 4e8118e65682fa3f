#include "nodes/builtin.hpp"

#include "nodes/association/register.hpp"
#include "nodes/boxes/register.hpp"
#include "nodes/eval/register.hpp"
#include "nodes/features/register.hpp"
#include "nodes/fusion/register.hpp"
#include "nodes/inference/register.hpp"
#include "nodes/ingest/register.hpp"
#include "nodes/lifting/register.hpp"
#include "nodes/masks/register.hpp"
#include "nodes/splat/register.hpp"
#include "nodes/synth/register.hpp"
#include "nodes/text/register.hpp"
#include "nodes/vlm/register.hpp"

namespace gslift {

void register_builtin_nodes(Registry& registry) {
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
  register_vlm_nodes(registry);
  register_masks_nodes(registry);
  register_fusion_nodes(registry);
}

}  // namespace gslift
