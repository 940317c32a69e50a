// A symmetric box for the search tests (cem_search_test.cc, bayes_search_test.cc).
#ifndef JUGGLE_PLANNER_TESTING_SEARCH_BOX_H_
#define JUGGLE_PLANNER_TESTING_SEARCH_BOX_H_

#include "planner/cem_search.h"

namespace juggle::testing {

// `dim` variables in [−limit, limit], each with the initial spread `sigma`.
inline SearchSpace Box(int dim, double limit, double sigma) {
  SearchSpace s;
  s.lower.assign(dim, -limit);
  s.upper.assign(dim, limit);
  s.sigma.assign(dim, sigma);
  return s;
}

}  // namespace juggle::testing

#endif  // JUGGLE_PLANNER_TESTING_SEARCH_BOX_H_
