#include "planner/bayes_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace juggle {
namespace {

// Length scales tried at every fit, in units of the box (its width is 1 per variable); the one
// of highest marginal likelihood is used.
constexpr double kLengthScales[] = {0.05, 0.1, 0.2, 0.4, 0.8};
// The model's noise variance in units of the standardized target: a contact makes the cost
// jump where the model expects it smooth.
constexpr double kNoise = 1e-3;
// Candidates the model is fitted on: the best so far.
constexpr int kModelPoints = 64;

// Matérn 5/2 between two points of the unit box.
double Kernel(const double* a, const double* b, int dim, double length) {
  double r2 = 0;
  for (int d = 0; d < dim; ++d) r2 += (a[d] - b[d]) * (a[d] - b[d]);
  const double r = std::sqrt(5.0 * r2) / length;
  return (1 + r + r * r / 3) * std::exp(-r);
}

// A Gaussian process on points of the unit box with standardized targets.
class Gp {
 public:
  // `length` <= 0: the length scale of highest marginal likelihood among kLengthScales.
  // `noise`: the targets' noise variance in standardized units.
  Gp(const std::vector<double>& points, int dim, const std::vector<double>& y, double length,
     double noise = kNoise)
      : dim_(dim), noise_(noise) {
    n_ = static_cast<int>(y.size());
    points_ = points;
    double mean = 0;
    for (double v : y) mean += v;
    mean /= n_;
    double var = 0;
    for (double v : y) var += (v - mean) * (v - mean);
    mean_ = mean;
    scale_ = n_ > 1 && var > 0 ? std::sqrt(var / n_) : 1.0;
    z_.resize(n_);
    for (int i = 0; i < n_; ++i) z_[i] = (y[i] - mean_) / scale_;
    length_ = length;
    if (length <= 0) {
      double best_evidence = -std::numeric_limits<double>::infinity();
      for (double l : kLengthScales) {
        Fit(l);
        // log p(z) up to a constant: −½ zᵀK⁻¹z − Σ log L_ii.
        const double evidence =
            -0.5 * z_.dot(alpha_) - llt_.matrixLLT().diagonal().array().log().sum();
        if (evidence > best_evidence) best_evidence = evidence, length_ = l;
      }
    }
    Fit(length_);
  }
  double length() const { return length_; }

  // Mean and standard deviation of the standardized target at `x`.
  void Predict(const double* x, double* mean, double* sd) const {
    Eigen::VectorXd k(n_);
    for (int i = 0; i < n_; ++i) k[i] = Kernel(x, &points_[size_t(i) * dim_], dim_, length_);
    *mean = k.dot(alpha_);
    const Eigen::VectorXd v = llt_.matrixL().solve(k);
    *sd = std::sqrt(std::max(1.0 - v.squaredNorm(), 1e-12));
  }
  double Standardize(double y) const { return (y - mean_) / scale_; }
  double Unstandardize(double z) const { return mean_ + scale_ * z; }

 private:
  void Fit(double length) {
    Eigen::MatrixXd k(n_, n_);
    for (int i = 0; i < n_; ++i) {
      for (int j = 0; j <= i; ++j) {
        k(i, j) = k(j, i) =
            Kernel(&points_[size_t(i) * dim_], &points_[size_t(j) * dim_], dim_, length);
      }
      k(i, i) += noise_;
    }
    llt_.compute(k);
    alpha_ = llt_.solve(z_);
  }

  int dim_ = 0, n_ = 0;
  double noise_ = kNoise;
  std::vector<double> points_;
  Eigen::VectorXd z_, alpha_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  double mean_ = 0, scale_ = 1, length_ = kLengthScales[0];
};

double ExpectedImprovement(double best, double mean, double sd) {
  const double z = (best - mean) / sd;
  const double cdf = 0.5 * std::erfc(-z / std::sqrt(2.0));
  const double pdf = std::exp(-0.5 * z * z) / std::sqrt(2 * M_PI);
  return (best - mean) * cdf + sd * pdf;
}

double Target(double cost) { return std::log1p(std::max(cost, 0.0)); }

// The kModelPoints lowest `targets` and their points (`dim` values each in `units`): the region
// worth modelling, and a bound on the model's cost.
void BestPoints(const std::vector<double>& units, const std::vector<double>& targets, int dim,
                std::vector<double>* best_units, std::vector<double>* best_targets) {
  std::vector<int> order(targets.size());
  std::iota(order.begin(), order.end(), 0);
  const int kept = std::min<int>(kModelPoints, static_cast<int>(order.size()));
  std::partial_sort(order.begin(), order.begin() + kept, order.end(),
                    [&](int i, int j) { return targets[i] < targets[j]; });
  best_units->clear();
  best_targets->clear();
  for (int k = 0; k < kept; ++k) {
    best_units->insert(best_units->end(), units.begin() + size_t(order[k]) * dim,
                       units.begin() + size_t(order[k] + 1) * dim);
    best_targets->push_back(targets[order[k]]);
  }
}

}  // namespace

absl::StatusOr<CemResult> MinimizeBayes(const SearchSpace& space, const BayesSettings& settings,
                                        const std::vector<std::vector<double>>& seeds, Rng* rng,
                                        const BatchCost& cost) {
  const int dim = space.dim();
  std::vector<double> incumbent = seeds.front();
  incumbent.resize(dim, 0.0);
  auto clamp = [&](double* x) {
    for (int d = 0; d < dim; ++d) x[d] = std::clamp(x[d], space.lower[d], space.upper[d]);
  };
  clamp(incumbent.data());
  // The searched variables and their place in the unit box.
  std::vector<int> active;
  for (int d = 0; d < dim; ++d) {
    if (space.upper[d] > space.lower[d] && space.sigma[d] > 0) active.push_back(d);
  }
  const int a = static_cast<int>(active.size());
  auto to_unit = [&](const double* x, double* u) {
    for (int i = 0; i < a; ++i) {
      const int d = active[i];
      u[i] = (x[d] - space.lower[d]) / (space.upper[d] - space.lower[d]);
    }
  };
  auto from_unit = [&](const double* u, double* x) {
    std::copy(incumbent.begin(), incumbent.end(), x);
    for (int i = 0; i < a; ++i) {
      const int d = active[i];
      x[d] = space.lower[d] + std::clamp(u[i], 0.0, 1.0) * (space.upper[d] - space.lower[d]);
    }
  };

  CemResult result;
  // Every candidate evaluated so far: its variables, its place in the unit box, its cost and
  // the model's target.
  std::vector<double> xs, units, seen_costs, targets;
  std::vector<double> costs;
  auto evaluate = [&](const std::vector<double>& batch) -> absl::Status {
    const int n = static_cast<int>(batch.size()) / dim;
    costs.assign(n, 0.0);
    if (absl::Status s = cost(batch, n, std::numeric_limits<double>::infinity(), &costs);
        !s.ok()) {
      return s;
    }
    for (int i = 0; i < n; ++i) {
      const double* x = batch.data() + size_t(i) * dim;
      if (result.evaluations == 0) {
        result.incumbent_cost = result.best_cost = costs[i];
        result.best.assign(x, x + dim);
      } else if (costs[i] < result.best_cost) {
        result.best_cost = costs[i];
        result.best.assign(x, x + dim);
      }
      ++result.evaluations;
      xs.insert(xs.end(), x, x + dim);
      units.resize(units.size() + a);
      to_unit(x, &units[units.size() - a]);
      seen_costs.push_back(costs[i]);
      targets.push_back(Target(costs[i]));
    }
    ++result.iterations;
    result.iteration_best.push_back(result.best_cost);
    return absl::OkStatus();
  };

  // The seeds and samples around the incumbent, in one call.
  std::vector<double> batch(incumbent);
  for (size_t s = 1; s < seeds.size(); ++s) {
    std::vector<double> x = seeds[s];
    x.resize(dim, 0.0);
    clamp(x.data());
    batch.insert(batch.end(), x.begin(), x.end());
  }
  const int first = std::min(settings.evaluations,
                             static_cast<int>(seeds.size()) + (a > 0 ? settings.initial : 0));
  while (static_cast<int>(batch.size()) / dim < first) {
    std::vector<double> x(incumbent);
    for (int d : active) x[d] += space.sigma[d] * rng->Normal();
    clamp(x.data());
    batch.insert(batch.end(), x.begin(), x.end());
  }
  batch.resize(size_t(first) * dim);
  if (absl::Status s = evaluate(batch); !s.ok()) return s;

  std::vector<double> u(a), x(dim), best_u(a), unit_sigma(a);
  for (int i = 0; i < a; ++i) {
    const int d = active[i];
    unit_sigma[i] = space.sigma[d] / (space.upper[d] - space.lower[d]);
  }
  while (a > 0 && result.evaluations < settings.evaluations &&
         result.best_cost > settings.stop_below) {
    const int picks = std::min(settings.batch, settings.evaluations - result.evaluations);
    // The model of the best candidates so far, its length scale fitted once per batch.
    std::vector<double> design_units, design_targets;
    BestPoints(units, targets, a, &design_units, &design_targets);
    double length = 0;
    batch.clear();
    // Around the best so far at the sigma's and a quarter of it, and anywhere in the box.
    to_unit(result.best.data(), best_u.data());
    for (int p = 0; p < picks; ++p) {
      const Gp gp(design_units, a, design_targets, length);
      length = gp.length();
      const double best = gp.Standardize(
          *std::min_element(design_targets.begin(), design_targets.end()));
      double top = -1;
      std::vector<double> chosen(a);
      for (int c = 0; c < settings.acquisition_points; ++c) {
        const int kind = c % 3;
        for (int i = 0; i < a; ++i) {
          if (kind == 0) u[i] = rng->Uniform();
          else u[i] = best_u[i] + (kind == 1 ? 0.25 : 1.0) * unit_sigma[i] * rng->Normal();
          u[i] = std::clamp(u[i], 0.0, 1.0);
        }
        double mean = 0, sd = 1;
        gp.Predict(u.data(), &mean, &sd);
        const double ei = ExpectedImprovement(best, mean, sd);
        if (ei > top) top = ei, chosen = u;
      }
      // Believe the model at the chosen point, so the next pick looks elsewhere.
      double mean = 0, sd = 1;
      gp.Predict(chosen.data(), &mean, &sd);
      design_units.insert(design_units.end(), chosen.begin(), chosen.end());
      design_targets.push_back(gp.Unstandardize(mean));
      from_unit(chosen.data(), x.data());
      batch.insert(batch.end(), x.begin(), x.end());
    }
    if (absl::Status s = evaluate(batch); !s.ok()) return s;
  }
  if (a > 0 && settings.answer_noise > 0 && result.best_cost <= settings.stop_below) {
    // Of the candidates at or below the bar, the one whose neighbourhood the smoothing model
    // rates best.
    std::vector<int> good;
    for (int i = 0; i < result.evaluations; ++i) {
      if (seen_costs[i] <= settings.stop_below) good.push_back(i);
    }
    std::vector<double> model_units, model_targets;
    BestPoints(units, targets, a, &model_units, &model_targets);
    const Gp smooth(model_units, a, model_targets, 0, settings.answer_noise);
    double lowest = std::numeric_limits<double>::infinity();
    for (int i : good) {
      double mean = 0, sd = 1;
      smooth.Predict(&units[size_t(i) * a], &mean, &sd);
      if (mean < lowest) {
        lowest = mean;
        result.best.assign(xs.begin() + size_t(i) * dim, xs.begin() + size_t(i + 1) * dim);
        result.best_cost = seen_costs[i];
      }
    }
  }
  return result;
}

}  // namespace juggle
