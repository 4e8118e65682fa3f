// Binary forms of the port types for the stage cache (runtime/stage_cache.hpp): write() appends a
// value to a ByteWriter, read() rebuilds it exactly (floats bit for bit), so a node loaded from
// the cache hands its consumers the same bytes a fresh run would. Every read checks sizes against
// the archive and throws ArchiveError on damage. Capture and TextEncoder have no binary form:
// they hold file readers and code, and the nodes that make them are cheap, so they always run.
#pragma once

#include "base/byte_archive.hpp"
#include "nodes/scene/boxes.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/scene/instances.hpp"
#include "nodes/scene/label_maps.hpp"
#include "nodes/scene/lifted_instances.hpp"
#include "nodes/scene/masks.hpp"
#include "nodes/scene/prompts.hpp"
#include "nodes/scene/semantic_maps.hpp"
#include "nodes/scene/text_query_results.hpp"
#include "nodes/scene/view_poses.hpp"
#include "nodes/scene/vocabulary.hpp"

namespace gslift {

// Bumped whenever a binary form below changes: it is part of every cache key.
constexpr int kPortArchiveVersion = 2;

void write(ByteWriter& w, const BoxSet& v);
void read(ByteReader& r, BoxSet& v);
void write(ByteWriter& w, const GaussianModel& v);
void read(ByteReader& r, GaussianModel& v);
void write(ByteWriter& w, const InstanceSet& v);
void read(ByteReader& r, InstanceSet& v);
void write(ByteWriter& w, const LabelMapSet& v);
void read(ByteReader& r, LabelMapSet& v);
void write(ByteWriter& w, const ViewClassifiers& v);
void read(ByteReader& r, ViewClassifiers& v);
void write(ByteWriter& w, const LabelClassifier& v);
void read(ByteReader& r, LabelClassifier& v);
void write(ByteWriter& w, const LiftedInstances& v);
void read(ByteReader& r, LiftedInstances& v);
void write(ByteWriter& w, const MaskSet& v);
void read(ByteReader& r, MaskSet& v);
void write(ByteWriter& w, const PromptSet& v);
void read(ByteReader& r, PromptSet& v);
void write(ByteWriter& w, const SemanticMaps& v);
void read(ByteReader& r, SemanticMaps& v);
void write(ByteWriter& w, const TextQueryResults& v);
void read(ByteReader& r, TextQueryResults& v);
void write(ByteWriter& w, const Vocabulary& v);
void read(ByteReader& r, Vocabulary& v);
void write(ByteWriter& w, const ViewPoses& v);
void read(ByteReader& r, ViewPoses& v);

// The pieces the port types are made of, for tests and for new port types.
void write(ByteWriter& w, const cv::Mat& m);
void read(ByteReader& r, cv::Mat& m);
void write(ByteWriter& w, const Eigen::MatrixXf& m);
void read(ByteReader& r, Eigen::MatrixXf& m);

}  // namespace gslift
