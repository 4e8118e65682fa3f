// One term of the reconstruction's objective (the idea of Ceres' cost functions: each term owns
// its params and its derivative, and the training loop only asks each for its value and its
// gradient). reconstruct() trains over a list of terms (loss_terms.hpp); a new term is one file
// with its class and factory, and one line in that list.
#pragma once

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

#include "nodes/scene/camera.hpp"
#include "nodes/scene/gaussian_model.hpp"
#include "nodes/splat/rasterizer.hpp"
#include "nodes/splat/training_targets.hpp"

namespace gslift {

// When a term joins the training: from the first `start` fraction of the steps on, every
// `every`-th step.
struct TermSchedule {
  double start = 0;
  int every = 1;
  bool active(int step, int iterations) const {
    return step >= start * iterations && step % std::max(every, 1) == 0;
  }
};

// What a term sees of one training step: the model, the view's camera at the step's resolution,
// its targets and the step's render.
struct StepRender {
  const GaussianModel& model;
  const Camera& camera;
  const Pose& pose;
  const TargetImages& target;
  const RenderOutput& out;
};

// Where a term's gradient enters, which is also the order the loop evaluates them in:
//  Image: dL/d(the rendered channels), before the rasterizer's backward pass takes them to the
//    model (photometric, depth, normal);
//  Ray: dL/d(model) by a pass of its own over the step's tile lists, after that backward pass
//    (line of sight);
//  Model: dL/d(model) from the parameters alone, no render (flatness, edge extent).
enum class TermStage { Image, Ray, Model };

class LossTerm {
 public:
  LossTerm(double weight, TermSchedule schedule) : weight_(weight), schedule_(schedule) {}
  virtual ~LossTerm() = default;

  // The term's name: records call its final value loss_<name>.
  virtual const char* name() const = 0;
  virtual TermStage stage() const = 0;
  // Whether the term joins at this step for this target (its schedule, and what it needs: a
  // depth prior, normals).
  bool applies(int step, int iterations, const TargetImages& target) const {
    return schedule_.active(step, iterations) && has_target(target);
  }
  // The channels the step's render must hold for the term (it joins this step).
  virtual void request(RenderSettings&) const {}
  // The term's unweighted value at this step; adds weight x its gradient into `image` (Image
  // stage) or `model` (Ray and Model stages).
  virtual double evaluate(const StepRender& step, RenderGrads& image, ModelGrads& model) = 0;

  double weight() const { return weight_; }

 protected:
  virtual bool has_target(const TargetImages&) const { return true; }

 private:
  double weight_;
  TermSchedule schedule_;
};

// `into` += weight x the image's values (flat, as RenderGrads holds them); an empty `into` becomes
// the scaled image.
void add_scaled(std::vector<float>& into, const cv::Mat& image, double weight);

// `into` += weight x grad, element by element (a gradient of the model's parameters).
void add_scaled(std::vector<float>& into, const std::vector<float>& grad, double weight);

}  // namespace gslift
