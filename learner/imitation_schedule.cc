#include "learner/imitation_schedule.h"

#include <algorithm>
#include <cmath>

namespace juggle {

ImitationTerm ImitationFor(const config::ImitationConfig& im, int64_t iteration,
                           const DemoBuffer* demos) {
  ImitationTerm term;
  if (demos == nullptr) return term;
  if (demos->size() >= im.min_buffer()) {
    term.demos = demos;
    if (im.min_label_std() > 0) {
      const double floor = im.min_label_std() * im.min_label_std();
      for (double var : demos->LabelVariance()) {
        term.action_weights.push_back(static_cast<float>(1.0 / std::max(var, floor)));
      }
    }
  }
  const int64_t k = iteration - im.pretrain_iterations();
  if (k < 0) {
    term.clone_only = true;
    term.clone_steps = im.clone_steps();
    term.clone_minibatch = im.clone_minibatch();
    term.clone_lr = im.clone_lr();
  } else {
    term.weight = im.weight() * std::max(std::pow(im.decay(), double(k)), im.floor_fraction());
  }
  return term;
}

}  // namespace juggle
