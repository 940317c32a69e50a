// `juggle bench physics`: where a control step's physics time goes, and what the model's
// solver options would save. Replays the states a zero-action env visits as bare mj_step calls
// (bench/physics_reference.h) on the config's model and on variants of it (one mjOption field
// changed each), interleaved in chunks of states so machine noise hits every variant alike. For each
// variant: substeps/s against the shipped model's, and how far one control step from the same
// state lands from the shipped model's (the physics it changes). For the shipped model: the
// share of each mj_step stage (MuJoCo's own timers). The last line is key=value pairs.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "bench/benchmarks.h"
#include "bench/physics_reference.h"
#include "envs/mujoco_model.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/spec.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleSpec;
using Clock = std::chrono::steady_clock;

struct ModelVariant {
  std::string key;          // the key=value line's name
  std::string description;  // what changed
  std::function<void(mjModel*)> change;
};

std::vector<ModelVariant> Variants() {
  return {
      {"shipped", "the config's model", [](mjModel*) {}},
      {"dense", "jacobian dense (shipped: sparse)", [](mjModel* m) { m->opt.jacobian = mjJAC_DENSE; }},
      {"cg", "solver CG", [](mjModel* m) { m->opt.solver = mjSOL_CG; }},
      {"pgs", "solver PGS", [](mjModel* m) { m->opt.solver = mjSOL_PGS; }},
      {"pyramidal", "cone pyramidal (shipped: elliptic)", [](mjModel* m) { m->opt.cone = mjCONE_PYRAMIDAL; }},
      {"tol1e-6", "solver tolerance 1e-6", [](mjModel* m) { m->opt.tolerance = 1e-6; }},
      {"no_warmstart", "no solver warm start", [](mjModel* m) { m->opt.disableflags |= mjDSBL_WARMSTART; }},
      {"no_filterparent", "parent-child collision filter off (broadphase sees every pair)",
       [](mjModel* m) { m->opt.disableflags |= mjDSBL_FILTERPARENT; }},
  };
}

struct Replay {
  double seconds = 0;
  double steps = 0;
  std::vector<double> end_qpos;  // every state's qpos after one control step, concatenated
  long iterations = 0, contacts = 0;
  double substeps_per_s() const { return seconds > 0 ? steps / seconds : 0; }
};

// Replays states [begin, end) as `substeps` mj_steps each on `d` and adds to `out` (end
// positions only on the first pass, `keep_positions`).
void ReplayStates(const mjModel* m, mjData* d, const std::vector<VisitedState>& states,
                  size_t begin, size_t end, int substeps, bool keep_positions, Replay* out) {
  const auto start = Clock::now();
  for (size_t i = begin; i < end; ++i) {
    const VisitedState& s = states[i];
    mju_copy(d->qpos, s.qpos.data(), m->nq);
    mju_copy(d->qvel, s.qvel.data(), m->nv);
    mju_copy(d->qfrc_applied, s.qfrc_applied.data(), m->nv);
    for (int k = 0; k < substeps; ++k) {
      mj_step(m, d);
      out->iterations += d->solver_iter;
      out->contacts += d->ncon;
    }
    if (keep_positions) out->end_qpos.insert(out->end_qpos.end(), d->qpos, d->qpos + m->nq);
  }
  out->seconds += std::chrono::duration<double>(Clock::now() - start).count();
  out->steps += double(end - begin) * substeps;
}

// The median and the largest distance between two replays' end positions, over the states: the
// free joints' translations (m) and the ball's, separately from everything.
struct Drift {
  double median_m = 0, max_m = 0;
};

Drift BallDrift(const JuggleSpec& spec, const std::vector<double>& a, const std::vector<double>& b) {
  const int nq = spec.model()->nq, ball = spec.ball_qpos();
  std::vector<double> d;
  for (size_t s = 0; s + nq <= a.size(); s += nq) {
    d.push_back(std::hypot(a[s + ball] - b[s + ball], a[s + ball + 1] - b[s + ball + 1],
                           a[s + ball + 2] - b[s + ball + 2]));
  }
  if (d.empty()) return {};
  std::sort(d.begin(), d.end());
  return {d[d.size() / 2], d.back()};
}

Drift RootDrift(const std::vector<double>& a, const std::vector<double>& b, int nq) {
  std::vector<double> d;
  for (size_t s = 0; s + nq <= a.size(); s += nq) {
    d.push_back(std::hypot(a[s] - b[s], a[s + 1] - b[s + 1], a[s + 2] - b[s + 2]));
  }
  if (d.empty()) return {};
  std::sort(d.begin(), d.end());
  return {d[d.size() / 2], d.back()};
}

mjtNum SteadySeconds() {
  return std::chrono::duration<double>(Clock::now().time_since_epoch()).count();
}

// The shipped model's mj_step stages as shares of the step (MuJoCo's timers, on for this pass
// only).
void PrintStages(const mjModel* m, const std::vector<VisitedState>& states, int substeps) {
  mjcb_time = SteadySeconds;
  MjDataPtr data(mj_makeData(m));
  mjData* d = data.get();
  double total[mjNTIMER] = {0};
  for (const VisitedState& s : states) {
    mju_copy(d->qpos, s.qpos.data(), m->nq);
    mju_copy(d->qvel, s.qvel.data(), m->nv);
    mju_copy(d->qfrc_applied, s.qfrc_applied.data(), m->nv);
    for (int k = 0; k < substeps; ++k) {
      mj_step(m, d);
      for (int t = 0; t < mjNTIMER; ++t) {
        total[t] += d->timer[t].duration;
        d->timer[t].duration = 0;
        d->timer[t].number = 0;
      }
    }
  }
  mjcb_time = nullptr;
  struct Stage {
    const char* name;
    int timer;
  };
  const Stage stages[] = {
      {"kinematics, com, tendons, transmission", mjTIMER_POS_KINEMATICS},
      {"inertia (mass matrix and its factor)", mjTIMER_POS_INERTIA},
      {"collision detection", mjTIMER_POS_COLLISION},
      {"making constraints", mjTIMER_POS_MAKE},
      {"projecting constraints", mjTIMER_POS_PROJECT},
      {"velocity (com velocities, passive forces, bias)", mjTIMER_VELOCITY},
      {"actuation", mjTIMER_ACTUATION},
      {"acceleration (unconstrained)", mjTIMER_ACCELERATION},
      {"constraint solver", mjTIMER_CONSTRAINT},
  };
  const double step = total[mjTIMER_STEP];
  double named = 0;
  std::printf("shipped model, share of mj_step's time per stage (%.1f us per step):\n",
              1e6 * step / (double(states.size()) * substeps));
  for (const Stage& s : stages) {
    std::printf("  %-48s %5.1f %%\n", s.name, 100 * total[s.timer] / step);
    named += total[s.timer];
  }
  std::printf("  %-48s %5.1f %%\n", "integration and the rest (implicit damping: a 2nd factor)",
              100 * (step - named) / step);
}

}  // namespace

absl::Status RunPhysicsBench(const PhysicsBenchOptions& o) {
  absl::StatusOr<LoadedConfig> config = LoadRunConfig(o.config);
  if (!config.ok()) return config.status();
  auto spec = JuggleSpec::Create(*config);
  if (!spec.ok()) return spec.status();
  const int substeps = (*spec)->env().substeps();
  const std::vector<VisitedState> states = RecordEnvStates(*spec, o.states);
  const mjModel* shipped = (*spec)->model();
  std::printf("%zu states a zero-action env visits (%s), %d substeps each, %d rounds\n",
              states.size(), o.config.c_str(), substeps, o.repeats);

  const std::vector<ModelVariant> variants = Variants();
  std::vector<MjModelPtr> models;
  for (const ModelVariant& v : variants) {
    models.emplace_back(mj_copyModel(nullptr, shipped));
    v.change(models.back().get());
  }
  std::vector<MjDataPtr> datas;
  for (const MjModelPtr& model : models) datas.emplace_back(mj_makeData(model.get()));
  // Chunks of 50 states, every variant in turn on each: the machine's speed drifts over
  // seconds, and this way it drifts under all of them alike.
  constexpr size_t kChunk = 50;
  std::vector<Replay> replays(variants.size());
  for (int r = 0; r < o.repeats; ++r) {
    for (size_t begin = 0; begin < states.size(); begin += kChunk) {
      const size_t end = std::min(states.size(), begin + kChunk);
      for (size_t v = 0; v < variants.size(); ++v) {
        ReplayStates(models[v].get(), datas[v].get(), states, begin, end, substeps, r == 0,
                     &replays[v]);
      }
    }
    std::printf("round %d: shipped %.0f substeps/s so far\n", r + 1, replays[0].substeps_per_s());
    std::fflush(stdout);
  }
  PrintStages(shipped, states, substeps);

  std::printf("%-18s %-62s %9s %6s %6s %6s %14s %14s\n", "variant", "change", "substeps/s",
              "ratio", "iters", "ncon", "ball drift m", "root drift m");
  std::string keys;
  const int nq = shipped->nq;
  for (size_t v = 0; v < variants.size(); ++v) {
    const double ratio = replays[v].substeps_per_s() / replays[0].substeps_per_s();
    const Drift ball = BallDrift(**spec, replays[v].end_qpos, replays[0].end_qpos);
    const Drift root = RootDrift(replays[v].end_qpos, replays[0].end_qpos, nq);
    std::printf("%-18s %-62s %9.0f %6.3f %6.2f %6.2f %6.1e/%6.1e %6.1e/%6.1e\n",
                variants[v].key.c_str(), variants[v].description.c_str(),
                replays[v].substeps_per_s(), ratio, replays[v].iterations / replays[v].steps,
                replays[v].contacts / replays[v].steps, ball.median_m, ball.max_m,
                root.median_m, root.max_m);
    char buf[160];
    std::snprintf(buf, sizeof(buf), "%s%s_over_shipped=%.3f", keys.empty() ? "" : " ",
                  variants[v].key.c_str(), ratio);
    keys += buf;
  }
  std::printf("(drift: median/max over the states of the distance after one control step to the "
              "shipped model's, from the same state)\n");
  // The cross-checks of the replays themselves: the shipped model replayed again on fresh data
  // (exactly the same: the replay is deterministic), and the dense Jacobian against the sparse
  // one (rounding only: another path through the same equations).
  Replay again;
  MjDataPtr fresh(mj_makeData(shipped));
  ReplayStates(shipped, fresh.get(), states, 0, states.size(), substeps, true, &again);
  const Drift self = BallDrift(**spec, again.end_qpos, replays[0].end_qpos);
  const Drift dense_ball = BallDrift(**spec, replays[1].end_qpos, replays[0].end_qpos);
  const Drift dense_root = RootDrift(replays[1].end_qpos, replays[0].end_qpos, nq);
  const bool dense_agrees = dense_ball.max_m < 1e-9 && dense_root.max_m < 1e-9;
  std::printf("shipped_substeps_per_s=%.0f %s shipped_ball_drift_max_m=%g dense_drift_within_1e-9=%d\n",
              replays[0].substeps_per_s(), keys.c_str(), self.max_m, dense_agrees ? 1 : 0);
  return absl::OkStatus();
}

}  // namespace juggle
