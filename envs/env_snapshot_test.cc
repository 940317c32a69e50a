// Snapshots are exact: an env restored from a snapshot steps bit for bit as the original, for
// every env (soccer juggling, the toss task env, the toss in-loop env); snapshots of another
// family, model or config are refused.
//
// How a copy is compared with its original (StepInLockstep): both are stepped with the same
// actions, through episode ends and the resets after them, and compared right after the restore,
// after every step and after every reset, bit for bit:
//   - what a user of an env sees through Env (CompareEnvs): qpos, qvel and act by index, then the
//     rest of mjData (PhysicsSnapshot::Equals: controls, applied forces, warm start, contacts,
//     derived quantities, time, warnings), the reward and outcome, the observation, the counters,
//     the edge events, the annotations and the episode metrics;
//   - the env's own variables (Compare*Variables): every field of a snapshot taken from each env
//     afterwards, the next draws of their random streams, the runtime of the loop env.
// The copy is a differently seeded env (the toss task copy even runs the other arm) stepped into
// another state before the restore, so a variable that a restore forgot keeps a value of its own.
// The "...NoticesAStale..." tests show that the comparison can fail: a snapshot with one variable
// changed (what a restore that forgot it would leave) is told apart through Env alone.
#include "envs/env_snapshot.h"

#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "absl/strings/str_cat.h"
#include "envs/registry.h"
#include "envs/soccer_juggle/env.h"
#include "envs/testing/test_configs.h"
#include "envs/toss/loop_env.h"
#include "envs/toss/outcomes.h"
#include "envs/toss/task_env.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using soccer_juggle::JuggleEnv;
using soccer_juggle::JuggleEnvState;
using soccer_juggle::JuggleSnapshot;
using toss::Hand;
using toss::TossJuggler;
using toss::TossLoopEnv;
using toss::TossLoopSnapshot;
using toss::TossTaskEnv;
using toss::TossTaskSnapshot;
using toss::TossWorld;

std::shared_ptr<const EnvSpec> LoadFamilySpec(const std::string& name) {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// configs/<name>.textproto changed by `edit`, as a spec.
template <typename Edit>
std::shared_ptr<const EnvSpec> LoadEditedSpec(const std::string& name, Edit edit) {
  absl::StatusOr<LoadedConfig> config = testing::LoadShippedConfig(name);
  if (!config.ok()) return nullptr;
  edit(&config->run);
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  EXPECT_TRUE(spec.ok()) << spec.status();
  return spec.ok() ? *spec : nullptr;
}

// ---------------------------------------------------------------------------------------------
// The comparisons.

// The first difference found ("" while none).
class Differences {
 public:
  void Check(bool same, const std::string& what) {
    if (!same && first_.empty()) first_ = what;
  }
  bool any() const { return !first_.empty(); }
  const std::string& first() const { return first_; }

 private:
  std::string first_;
};

// Bitwise equality (doubles: −0 and +0 differ, a NaN equals the same NaN). REQUIRES: T has no
// padding (numbers, arrays of numbers, structs of doubles).
template <typename T>
bool Same(const T& x, const T& y) {
  static_assert(std::is_trivially_copyable_v<T>);
  return std::memcmp(&x, &y, sizeof(T)) == 0;
}

template <typename T>
bool SameVector(const std::vector<T>& x, const std::vector<T>& y) {
  static_assert(std::is_trivially_copyable_v<T>);
  return x.size() == y.size() &&
         (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(T)) == 0);
}

// Field by field: SwingAdjust holds two bools between its doubles, and the padding after them
// is not part of its value (Same's memcmp would read it).
bool SameSwingAdjust(const soccer_juggle::SwingAdjust& a, const soccer_juggle::SwingAdjust& b) {
  static_assert(sizeof(soccer_juggle::SwingAdjust) == 12 * sizeof(double),
                "SwingAdjust changed: compare its new fields here");
  return Same(a.hip, b.hip) && Same(a.knee, b.knee) && Same(a.abduction, b.abduction) &&
         Same(a.phase, b.phase) && Same(a.ankle, b.ankle) && a.placing == b.placing &&
         a.stance_roll_left_kick == b.stance_roll_left_kick && Same(a.place_hip, b.place_hip) &&
         Same(a.place_abduction, b.place_abduction) && Same(a.lean_pitch, b.lean_pitch) &&
         Same(a.lean_roll, b.lean_roll) && Same(a.head_phase, b.head_phase) &&
         Same(a.stance_roll, b.stance_roll);
}

// The next draws of copies of two random streams agree (the streams are left as they are).
bool SameDraws(Rng a, Rng b) {
  for (int i = 0; i < 4; ++i) {
    if (a.NextU64() != b.NextU64()) return false;
  }
  return true;
}

// What anyone holding an Env sees (EnvPool, the planner, the evaluation, recordings).
void CompareEnvs(const EnvSpec& spec, const Env& a, const Env& b, Differences* d) {
  const mjModel* m = spec.model();
  const mjData* x = a.data();
  const mjData* y = b.data();
  for (int i = 0; i < m->nq; ++i) d->Check(Same(x->qpos[i], y->qpos[i]), absl::StrCat("qpos[", i, "]"));
  for (int i = 0; i < m->nv; ++i) d->Check(Same(x->qvel[i], y->qvel[i]), absl::StrCat("qvel[", i, "]"));
  for (int i = 0; i < m->na; ++i) d->Check(Same(x->act[i], y->act[i]), absl::StrCat("act[", i, "]"));
  PhysicsSnapshot physics;
  physics.Save(m, x);
  d->Check(physics.Equals(y), "the rest of mjData (PhysicsSnapshot::Equals)");
  std::vector<float> obs_a(spec.obs_dim()), obs_b(spec.obs_dim());
  a.WriteObservation(obs_a.data());
  b.WriteObservation(obs_b.data());
  for (int i = 0; i < spec.obs_dim(); ++i) {
    d->Check(Same(obs_a[i], obs_b[i]), absl::StrCat("observation[", i, "]"));
  }
  d->Check(a.steps() == b.steps(), "steps()");
  d->Check(a.completions() == b.completions(), "completions()");
  d->Check(a.juggles() == b.juggles(), "juggles()");
  d->Check(a.node() == b.node(), "node()");
  d->Check(a.events() == b.events(), "events()");
  std::vector<double> notes_a, notes_b;
  a.AppendAnnotations(&notes_a);
  b.AppendAnnotations(&notes_b);
  d->Check(SameVector(notes_a, notes_b), "annotations");
  std::vector<NamedValue> metrics_a, metrics_b;
  a.AppendEpisodeMetrics(&metrics_a);
  b.AppendEpisodeMetrics(&metrics_b);
  d->Check(metrics_a.size() == metrics_b.size(), "episode metrics");
  for (size_t i = 0; i < metrics_a.size() && i < metrics_b.size(); ++i) {
    d->Check(metrics_a[i].name == metrics_b[i].name && Same(metrics_a[i].value, metrics_b[i].value),
             absl::StrCat("episode metric ", metrics_a[i].name));
  }
}

void CompareWorlds(const TossWorld::Snapshot& a, const TossWorld::Snapshot& b,
                   const std::string& who, Differences* d) {
  for (int i = 0; i < toss::kTossBalls; ++i) {
    d->Check(a.balls[i].mode == b.balls[i].mode && a.balls[i].holder == b.balls[i].holder,
             absl::StrCat(who, "ball ", i, "'s mode or holder"));
  }
  d->Check(Same(a.target, b.target), who + "PD targets");
  d->Check(Same(a.prev_speed, b.prev_speed), who + "joint speeds before the last step");
  d->Check(Same(a.prev_ball, b.prev_ball), who + "ball positions before the last step");
  d->Check(Same(a.prev_palm, b.prev_palm), who + "palm positions before the last step");
  d->Check(a.diverged == b.diverged, who + "diverged");
}

// The toss task env's own variables, from a snapshot of each.
void CompareTossTaskVariables(const Env& a, const Env& b, Differences* d) {
  const std::unique_ptr<EnvSnapshot> sa = a.Snapshot(), sb = b.Snapshot();
  const auto* x = dynamic_cast<const TossTaskSnapshot*>(sa.get());
  const auto* y = dynamic_cast<const TossTaskSnapshot*>(sb.get());
  if (x == nullptr || y == nullptr) return d->Check(false, "not toss task snapshots");
  d->Check(x->world.physics.Equals(b.data()) && y->world.physics.Equals(a.data()),
           "a snapshot's physics");
  const toss::TossTaskState& s = x->state;
  const toss::TossTaskState& t = y->state;
  d->Check(SameDraws(s.rng, t.rng), "the random stream's next draws");
  d->Check(s.hand == t.hand, "the acting hand");
  d->Check(Same(s.mirror, t.mirror), "mirror");
  d->Check(s.steps == t.steps, "steps");
  d->Check(s.completions == t.completions, "completions");
  d->Check(s.throw_value == t.throw_value, "throw_value");
  d->Check(s.release_step == t.release_step, "release_step");
  d->Check(s.released == t.released, "released");
  d->Check(Same(s.target_velocity, t.target_velocity), "target_velocity");
  d->Check(Same(s.release_velocity_error, t.release_velocity_error), "release_velocity_error");
  d->Check(Same(s.release_position_error, t.release_position_error), "release_position_error");
  CompareWorlds(x->world, y->world, "world: ", d);
}

void CompareHandEvents(const toss::HandEvents& a, const toss::HandEvents& b, const std::string& who,
                       Differences* d) {
  d->Check(a.caught == b.caught && Same(a.catch_height_error, b.catch_height_error) &&
               Same(a.catch_palm_speed, b.catch_palm_speed),
           who + "catch event");
  d->Check(a.released == b.released && a.value == b.value && a.good_throw == b.good_throw &&
               Same(a.release_position, b.release_position) &&
               Same(a.release_velocity, b.release_velocity) &&
               Same(a.target_velocity, b.target_velocity),
           who + "release event");
}

// The two-arm runtime as its public interface shows it; its private variables (beat clock, the
// balls' next beats, the wind estimate, the error sums) show through its results, events and the
// base controllers' targets, which the next step's physics follows.
void CompareJugglers(const TossJuggler& a, const TossJuggler& b, Differences* d) {
  TossWorld::Snapshot wa, wb;
  a.world().Save(&wa);
  b.world().Save(&wb);
  d->Check(wa.physics.Equals(b.world().data()), "juggler: world physics");
  CompareWorlds(wa, wb, "juggler world: ", d);
  const toss::JuggleRunResult& r = a.result();
  const toss::JuggleRunResult& s = b.result();
  d->Check(r.throws == s.throws && r.catches == s.catches && r.good_throws == s.good_throws &&
               r.releases == s.releases && r.end == s.end,
           "juggler: throws, catches, good throws, releases or end");
  d->Check(Same(r.seconds, s.seconds) && Same(r.mean_velocity_error, s.mean_velocity_error) &&
               Same(r.mean_position_error, s.mean_position_error) &&
               Same(r.max_velocity_error, s.max_velocity_error) &&
               Same(r.mean_catch_height_error, s.mean_catch_height_error),
           "juggler: seconds or release and catch errors");
  d->Check(r.velocity_error_by_value == s.velocity_error_by_value,
           "juggler: velocity errors by value");
  d->Check(SameVector(r.throw_starts, s.throw_starts) && SameVector(r.catch_starts, s.catch_starts),
           "juggler: recorded start states");
  d->Check(a.over() == b.over(), "juggler: over");
  if (a.over() && b.over()) d->Check(a.end_hand() == b.end_hand(), "juggler: end hand");
  d->Check(a.schedule().Name() == b.schedule().Name(), "juggler: schedule");
  for (Hand hand : {Hand::kRight, Hand::kLeft}) {
    const std::string who = absl::StrCat("juggler ", toss::HandName(hand), ": ");
    CompareHandEvents(a.events(hand), b.events(hand), who, d);
    d->Check(a.HoldsThrow(hand) == b.HoldsThrow(hand), who + "mode (HoldsThrow)");
    d->Check(a.IncomingBall(hand) == b.IncomingBall(hand), who + "incoming ball");
    float oa[toss::kTossThrowObs] = {}, ob[toss::kTossThrowObs] = {};
    a.WriteObservation(hand, oa);
    b.WriteObservation(hand, ob);
    d->Check(Same(oa, ob), who + "observation");
  }
}

// The loop env's own variables: its accessors, the runtime, and a snapshot of each.
void CompareLoopVariables(const Env& a, const Env& b, Differences* d) {
  const auto& x = dynamic_cast<const TossLoopEnv&>(a);
  const auto& y = dynamic_cast<const TossLoopEnv&>(b);
  d->Check(x.runs_started() == y.runs_started(), "runs_started()");
  d->Check(SameVector(x.failure_rates(), y.failure_rates()), "failure_rates()");
  CompareJugglers(x.juggler(), y.juggler(), d);
  const std::unique_ptr<EnvSnapshot> sa = a.Snapshot(), sb = b.Snapshot();
  const auto* s = dynamic_cast<const TossLoopSnapshot*>(sa.get());
  const auto* t = dynamic_cast<const TossLoopSnapshot*>(sb.get());
  if (s == nullptr || t == nullptr) return d->Check(false, "not toss loop snapshots");
  d->Check(SameDraws(s->rng, t->rng), "the random stream's next draws");
  d->Check(s->steps == t->steps && s->completions == t->completions, "snapshot: steps, completions");
  d->Check(s->runs_started == t->runs_started && s->run_pattern == t->run_pattern,
           "snapshot: runs started, run pattern");
  d->Check(SameVector(s->failure_rate, t->failure_rate), "snapshot: failure rates");
  CompareJugglers(*s->juggler, *t->juggler, d);
}

// The soccer env's own variables (JuggleEnv::state(), everything its snapshot holds).
void CompareSoccerVariables(const Env& a, const Env& b, Differences* d) {
  const JuggleEnvState& s = dynamic_cast<const JuggleEnv&>(a).state();
  const JuggleEnvState& t = dynamic_cast<const JuggleEnv&>(b).state();
  d->Check(SameDraws(s.rng, t.rng), "the random stream's next draws");
  const soccer_juggle::CursorState& c = s.cursor;
  const soccer_juggle::CursorState& e = t.cursor;
  d->Check(c.current == e.current && c.next == e.next && c.next_next == e.next_next,
           "cursor: nodes");
  d->Check(c.entered_by == e.entered_by && c.edge_to_next == e.edge_to_next &&
               c.edge_to_next_next == e.edge_to_next_next,
           "cursor: edges");
  d->Check(Same(c.phase, e.phase) && Same(c.phase_speed, e.phase_speed), "cursor: phase clock");
  d->Check(Same(c.apex_height, e.apex_height), "cursor: apex height");
  d->Check(c.completions == e.completions && c.juggles == e.juggles, "cursor: counters");
  d->Check(Same(s.reference, t.reference), "reference pose");
  d->Check(SameSwingAdjust(s.swing_adjust, t.swing_adjust), "kick feedback (swing_adjust)");
  d->Check(s.events == t.events, "events");
  d->Check(s.steps == t.steps, "steps");
  d->Check(s.kick_touched == t.kick_touched, "kick_touched");
  d->Check(s.kick_rewarded == t.kick_rewarded, "kick_rewarded");
  d->Check(s.touched_this_step == t.touched_this_step, "touched_this_step");
  d->Check(s.touched_body == t.touched_body, "touched_body");
  d->Check(s.bad_contact_geom == t.bad_contact_geom, "bad_contact_geom");
  d->Check(Same(s.reward.position, t.reward.position) &&
               Same(s.reward.orientation, t.reward.orientation) &&
               Same(s.reward.joint, t.reward.joint) && Same(s.reward.ball, t.reward.ball) &&
               Same(s.reward.scale, t.reward.scale) && Same(s.reward.kick, t.reward.kick),
           "reward terms");
  d->Check(Same(s.previous_action, t.previous_action), "previous_action");
  const std::unique_ptr<EnvSnapshot> sa = a.Snapshot(), sb = b.Snapshot();
  d->Check(sa->physics.Equals(b.data()) && sb->physics.Equals(a.data()), "a snapshot's physics");
}

using VariableComparison = std::function<void(const Env&, const Env&, Differences*)>;
using Actions = std::vector<std::vector<float>>;

// Random actions in ±`range` on the first `noisy` of `act_dim` dimensions, zero on the rest.
Actions RandomActions(uint64_t seed, int count, int act_dim, int noisy, double range) {
  Rng rng(seed);
  Actions actions(count, std::vector<float>(act_dim, 0.0f));
  for (std::vector<float>& a : actions) {
    for (int i = 0; i < noisy; ++i) a[i] = static_cast<float>(rng.Uniform(-range, range));
  }
  return actions;
}

// Steps `env` with actions[0, steps), resetting it after every episode that ends. Returns the
// episodes that ended.
int Advance(const EnvSpec& spec, Env* env, const Actions& actions, int steps) {
  const AdaptiveWalk walk(&spec.graph());
  int ended = 0;
  for (int t = 0; t < steps; ++t) {
    if (env->Step(actions[t].data(), walk).outcome != Outcome::kRunning) {
      ++ended;
      env->Reset(walk);
    }
  }
  return ended;
}

struct LockstepRun {
  int steps = 0;                 // steps compared
  std::vector<Outcome> endings;  // of the episodes that ended
  std::string difference;        // what differed first, and when; "" if nothing did
};

// Steps `original` and `copy` with actions[first], actions[first + 1], ... (the same for both)
// until `episodes` episodes have ended or `steps` steps are done, resetting both after every
// episode that ends (and once more at the end if the last step did not end one), so that the
// random draws of a reset are compared too. Compares CompareEnvs and `variables` (may be empty)
// right away, after every step and after every reset; stops at the first difference.
LockstepRun StepInLockstep(const EnvSpec& spec, Env* original, Env* copy, const Actions& actions,
                           int first, int steps, int episodes,
                           const VariableComparison& variables) {
  const AdaptiveWalk walk(&spec.graph());
  LockstepRun run;
  Differences d;
  auto compare = [&](const std::string& when) {
    CompareEnvs(spec, *original, *copy, &d);
    if (variables) variables(*original, *copy, &d);
    if (d.any()) run.difference = absl::StrCat(d.first(), ", ", when);
    return !d.any();
  };
  if (!compare("right after the restore")) return run;
  bool reset_last = false;
  for (int t = first; run.steps < steps && t < static_cast<int>(actions.size()); ++t) {
    const StepResult ra = original->Step(actions[t].data(), walk);
    const StepResult rb = copy->Step(actions[t].data(), walk);
    ++run.steps;
    d.Check(Same(ra.reward, rb.reward), "the reward");
    d.Check(ra.outcome == rb.outcome, "the outcome");
    if (!compare(absl::StrCat("after step ", run.steps))) return run;
    reset_last = ra.outcome != Outcome::kRunning;
    if (!reset_last) continue;
    run.endings.push_back(ra.outcome);
    original->Reset(walk);
    copy->Reset(walk);
    if (!compare(absl::StrCat("after the reset that followed step ", run.steps))) return run;
    if (static_cast<int>(run.endings.size()) >= episodes) return run;
  }
  if (!reset_last) {
    original->Reset(walk);
    copy->Reset(walk);
    compare("after a final reset");
  }
  return run;
}

// StepInLockstep from a snapshot taken after actions[0, at): when the original's episode ended
// with the last of them (`ended`), the envs are compared as they are (the ended episode's
// metrics), reset and compared again before `episodes` more episodes are stepped.
LockstepRun FromSnapshotPoint(const EnvSpec& spec, Env* original, Env* copy,
                              const Actions& actions, int at, bool ended, int episodes,
                              const VariableComparison& variables) {
  if (ended) {
    const LockstepRun end = StepInLockstep(spec, original, copy, actions, at, 0, 0, variables);
    if (!end.difference.empty()) return end;
  }
  return StepInLockstep(spec, original, copy, actions, at, 1000, episodes, variables);
}

int Count(const std::vector<Outcome>& endings, Outcome outcome) {
  int n = 0;
  for (Outcome o : endings) n += o == outcome;
  return n;
}

// One variable a restore could forget: changed in the snapshot before it is restored (a value
// other than the original's, as the copy's own would be) or in the copy after the restore.
struct StaleVariable {
  std::string name;
  std::function<void(EnvSnapshot*)> in_snapshot;  // may be empty
  std::function<void(Env*)> in_env;               // may be empty
};

template <typename S, typename F>
std::function<void(EnvSnapshot*)> Change(F f) {
  return [f](EnvSnapshot* s) { f(dynamic_cast<S*>(s)); };
}

// Another valid node or edge index than *i (the graphs here have at least two of each).
void Toggle(int* i) { *i = *i == 0 ? 1 : 0; }

// ---------------------------------------------------------------------------------------------
// Soccer juggling.

TEST(EnvSnapshotTest, SoccerCopyStepsBitForBitOverAJuggleCycle) {
  const std::shared_ptr<const EnvSpec> spec = LoadFamilySpec("right_foot_recipe");
  ASSERT_NE(spec, nullptr);
  const AdaptiveWalk walk(&spec->graph());
  // Zero actions for 7 steps, then the upper body (the first 14 actions: chest, neck, arms)
  // moves randomly.
  Actions actions(7, std::vector<float>(spec->act_dim(), 0.0f));
  for (std::vector<float>& a : RandomActions(77, 50, spec->act_dim(), 14, 0.2)) {
    actions.push_back(a);
  }
  std::unique_ptr<Env> original = spec->NewEnv(Rng(5));
  original->Reset(walk);
  // Mid-flight, so contacts, the kick feedback and the phase clock are all live.
  ASSERT_EQ(Advance(*spec, original.get(), actions, 7), 0);
  std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
  ASSERT_NE(snapshot, nullptr);
  EXPECT_EQ(snapshot->family(), "soccer_juggle");
  // A fresh env of the same spec with another random stream: the restore replaces it all.
  std::unique_ptr<Env> copy = spec->NewEnv(Rng(999));
  copy->Reset(walk);
  ASSERT_TRUE(copy->Restore(*snapshot).ok());
  EXPECT_TRUE(snapshot->physics.Equals(copy->data()));
  EXPECT_EQ(copy->steps(), original->steps());
  // A juggle cycle of the 1.4 m apex is about 43 control steps; the kick (about 14 steps from
  // here) is in it.
  const LockstepRun run = StepInLockstep(*spec, original.get(), copy.get(), actions, 7, 50, 1,
                                         CompareSoccerVariables);
  EXPECT_EQ(run.difference, "");
  EXPECT_GE(run.steps, 43);
}

TEST(EnvSnapshotTest, SoccerRestoreRewindsTheSameEnv) {
  const std::shared_ptr<const EnvSpec> spec = LoadFamilySpec("right_foot_recipe");
  ASSERT_NE(spec, nullptr);
  const AdaptiveWalk walk(&spec->graph());
  std::unique_ptr<Env> env = spec->NewEnv(Rng(6));
  env->Reset(walk);
  std::unique_ptr<EnvSnapshot> start = env->Snapshot();
  const std::vector<float> zero(spec->act_dim(), 0.0f);
  std::vector<std::unique_ptr<EnvSnapshot>> first_run;
  for (int t = 0; t < 30; ++t) {
    env->Step(zero.data(), walk);
    first_run.push_back(env->Snapshot());
  }
  ASSERT_TRUE(env->Restore(*start).ok());
  EXPECT_EQ(env->steps(), 0);
  // The whole state after every step, not the root height alone: the physics, and the env's
  // own variables against a copy restored from the first run's snapshot of that step.
  std::unique_ptr<Env> first = spec->NewEnv(Rng(60));
  for (int t = 0; t < 30; ++t) {
    env->Step(zero.data(), walk);
    ASSERT_TRUE(first_run[t]->physics.Equals(env->data())) << "step " << t;
    ASSERT_TRUE(first->Restore(*first_run[t]).ok());
    Differences d;
    CompareSoccerVariables(*env, *first, &d);
    ASSERT_EQ(d.first(), "") << "step " << t;
  }
}

// The window where the kick's variables matter: a copy restored a few steps before the ball
// touches the foot, at the touch, or anywhere between the touch and the kick's release (the
// kick feedback then holds its swing change, kick_touched is set, the kick reward not yet paid)
// steps through the touch, the release (reward term 5), the next DOWN node (a new cycle: the
// flags clear, the edge events of the transitions) and a reset (its start node and start state
// drawn from the random stream) exactly as the original does. previous_action_observation is on
// so that the last action is observed too.
class SoccerKickWindowTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spec_ = LoadEditedSpec("right_foot_recipe", [](config::RunConfig* run) {
      run->mutable_soccer_juggle()->mutable_env()->set_previous_action_observation(true);
    });
    ASSERT_NE(spec_, nullptr);
    actions_ = RandomActions(77, 200, spec_->act_dim(), 14, 0.2);
    // Where the touch, the release and the next cycle come with this seed and these actions.
    std::unique_ptr<Env> env = Original(0);
    const AdaptiveWalk walk(&spec_->graph());
    for (int t = 0; t < 150 && (next_cycle_ < 0 || t < next_cycle_ + kAfterCycle); ++t) {
      ASSERT_EQ(env->Step(actions_[t].data(), walk).outcome, Outcome::kRunning) << t;
      const JuggleEnvState& s = dynamic_cast<JuggleEnv&>(*env).state();
      if (touch_ < 0 && s.touched_this_step) touch_ = t + 1;
      if (touch_ >= 0 && release_ < 0 && s.reward.kick != 0) release_ = t + 1;
      if (release_ >= 0 && next_cycle_ < 0 && !s.kick_touched) next_cycle_ = t + 1;
    }
    ASSERT_GT(touch_, 3);
    ASSERT_GT(release_, touch_);
    ASSERT_GT(next_cycle_, release_);
  }

  // The original: seed 5, reset, stepped `steps` steps.
  std::unique_ptr<Env> Original(int steps) const {
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(5));
    env->Reset(AdaptiveWalk(&spec_->graph()));
    EXPECT_EQ(Advance(*spec_, env.get(), actions_, steps), 0);
    return env;
  }
  // Another env of the spec, elsewhere in another episode.
  std::unique_ptr<Env> Elsewhere() const {
    const AdaptiveWalk walk(&spec_->graph());
    std::unique_ptr<Env> env = spec_->NewEnv(Rng(999));
    env->Reset(walk);
    const std::vector<float> a(spec_->act_dim(), 0.1f);
    env->Step(a.data(), walk);
    return env;
  }
  // From step `at` through the next cycle's start and kAfterCycle steps more, then a reset.
  LockstepRun FromStep(int at, Env* original, Env* copy, const VariableComparison& variables) {
    return StepInLockstep(*spec_, original, copy, actions_, at, next_cycle_ + kAfterCycle - at,
                          1, variables);
  }

  static constexpr int kAfterCycle = 2;

  std::shared_ptr<const EnvSpec> spec_;
  Actions actions_;
  int touch_ = -1;       // the step after which the ball has touched the foot
  int release_ = -1;     // the step that paid the kick reward
  int next_cycle_ = -1;  // the step after which a new cycle has begun (kick flags cleared)
};

TEST_F(SoccerKickWindowTest, ACopyFollowsTheTouchReleaseAndNextCycleWithEveryVariable) {
  for (int at = touch_ - 3; at <= release_; ++at) {
    SCOPED_TRACE(absl::StrCat("restored after step ", at, " (touch after ", touch_,
                              ", release after ", release_, ")"));
    std::unique_ptr<Env> original = Original(at);
    std::unique_ptr<Env> copy = Elsewhere();
    ASSERT_TRUE(copy->Restore(*original->Snapshot()).ok());
    const LockstepRun run = FromStep(at, original.get(), copy.get(), CompareSoccerVariables);
    EXPECT_EQ(run.difference, "");
    EXPECT_EQ(run.steps, next_cycle_ + kAfterCycle - at);
  }
}

// Each change is what a restore that forgot the variable would leave; the comparison through
// Env alone notices every one. Not in the list, because the next step overwrites them before
// anything reads them: the reference pose (recomputed at the step's phase), touched_this_step,
// touched_body and the reward terms (cleared by every step; only state() shows them).
TEST_F(SoccerKickWindowTest, TheComparisonNoticesAStaleKickFlagFeedbackClockOrRandomStream) {
  using S = JuggleSnapshot;
  // Before the touch; after the last step in contact, before the release.
  const int before = touch_ - 1, after = release_ - 1;
  struct Case {
    int at;
    StaleVariable stale;
  };
  const std::vector<Case> cases = {
      {before, {"rng", Change<S>([](S* s) { s->state.rng = Rng(31337); }), {}}},
      {after, {"rng (after the touch)", Change<S>([](S* s) { s->state.rng = Rng(31337); }), {}}},
      {before, {"kick_touched", Change<S>([](S* s) { s->state.kick_touched = true; }), {}}},
      {before, {"kick_rewarded", Change<S>([](S* s) { s->state.kick_rewarded = true; }), {}}},
      {after, {"kick_touched (after the touch)",
               Change<S>([](S* s) { s->state.kick_touched = false; }), {}}},
      {after, {"swing_adjust (the kick feedback held after the touch)",
               Change<S>([](S* s) { s->state.swing_adjust.hip += 0.01; }), {}}},
      {before, {"cursor.phase", Change<S>([](S* s) { s->state.cursor.phase += 1e-3; }), {}}},
      {before, {"cursor.phase_speed",
                Change<S>([](S* s) { s->state.cursor.phase_speed *= 1.001; }), {}}},
      {before, {"cursor.apex_height",
                Change<S>([](S* s) { s->state.cursor.apex_height += 0.01; }), {}}},
      {before, {"cursor.next_next",
                Change<S>([](S* s) { Toggle(&s->state.cursor.next_next); }), {}}},
      {before, {"cursor.entered_by",
                Change<S>([](S* s) { Toggle(&s->state.cursor.entered_by); }), {}}},
      {before, {"cursor.edge_to_next",
                Change<S>([](S* s) { Toggle(&s->state.cursor.edge_to_next); }), {}}},
      {before, {"cursor.juggles", Change<S>([](S* s) { s->state.cursor.juggles += 1; }), {}}},
      {before, {"steps", Change<S>([](S* s) { s->state.steps += 1; }), {}}},
      {before, {"previous_action",
                Change<S>([](S* s) { s->state.previous_action[0] += 0.5f; }), {}}},
      {before, {"events", Change<S>([](S* s) { s->state.events.push_back({0}); }), {}}},
      {before, {"qvel alone (positions restored)", {},
                [](Env* env) { env->data()->qvel[7] += 1e-9; }}},
      {after, {"the solver's warm start (qacc_warmstart)", {},
               [](Env* env) { env->data()->qacc_warmstart[7] += 1e-3; }}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.stale.name);
    std::unique_ptr<Env> original = Original(c.at);
    std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
    if (c.stale.in_snapshot) c.stale.in_snapshot(snapshot.get());
    std::unique_ptr<Env> copy = Elsewhere();
    ASSERT_TRUE(copy->Restore(*snapshot).ok());
    if (c.stale.in_env) c.stale.in_env(copy.get());
    const LockstepRun run = FromStep(c.at, original.get(), copy.get(), nullptr);
    EXPECT_NE(run.difference, "") << "a stale " << c.stale.name << " went unnoticed";
    std::printf("  stale %-55s noticed: %s\n", c.stale.name.c_str(), run.difference.c_str());
  }
}

// ---------------------------------------------------------------------------------------------
// The toss task env (envs/toss/task_env.h): catch and throw, policies alone and residuals on the
// base controllers.

std::shared_ptr<const EnvSpec> TossTaskSpec(const std::string& name, bool throw_task) {
  return LoadEditedSpec(name, [throw_task](config::RunConfig* run) {
    run->mutable_toss()->set_task(throw_task ? config::THROW : config::CATCH);
  });
}

// A task env for the left arm (the originals act with the right), with another random stream,
// reset and stepped: every variable it holds differs from the original's.
std::unique_ptr<Env> TossTaskElsewhere(const EnvSpec& spec) {
  auto env = std::make_unique<TossTaskEnv>(
      std::dynamic_pointer_cast<const toss::TossSpec>(spec.shared_from_this()), Rng(1234),
      Hand::kLeft);
  const AdaptiveWalk walk(&spec.graph());
  env->Reset(walk);
  const std::vector<float> a(spec.act_dim(), 0.3f);
  env->Step(a.data(), walk);
  return env;
}

// Snapshots every 4 steps of a first episode and after its last step (the catch or the release,
// before the reset), each restored into a copy that then steps with the original through two
// more episode ends: the catch or release, the reset and its draws, a whole episode after it.
// Residuals on the base controllers are small (±0.1), the actions of the policies alone large
// (±0.5: the arm flails; some balls are still caught).
TEST(EnvSnapshotTest, TossTaskCopyFollowsCatchesAndThrowsWithVelocitiesAndEveryVariable) {
  struct Task {
    const char* config;
    bool throw_task;
    double action_range;
    Outcome success;
  };
  for (const Task& task : {Task{"toss_base", false, 0.1, toss::kCaught},
                           Task{"toss_base", true, 0.1, toss::kReleased},
                           Task{"toss_catch", false, 0.5, toss::kCaught},
                           Task{"toss_throw", true, 0.5, toss::kReleased}}) {
    SCOPED_TRACE(absl::StrCat(task.config, task.throw_task ? " THROW" : " CATCH"));
    const std::shared_ptr<const EnvSpec> spec = TossTaskSpec(task.config, task.throw_task);
    ASSERT_NE(spec, nullptr);
    const AdaptiveWalk walk(&spec->graph());
    const Actions actions =
        RandomActions(78, 1000, spec->act_dim(), spec->act_dim(), task.action_range);
    // The first episode's length.
    std::unique_ptr<Env> probe = spec->NewEnv(Rng(8));
    probe->Reset(walk);
    int length = 1;
    while (probe->Step(actions[length - 1].data(), walk).outcome == Outcome::kRunning) ++length;
    std::vector<int> points;
    for (int at = 0; at < length; at += 4) points.push_back(at);
    points.push_back(length);
    std::vector<Outcome> endings;
    for (const int at : points) {
      SCOPED_TRACE(absl::StrCat("restored after step ", at, " of ", length));
      std::unique_ptr<Env> original = spec->NewEnv(Rng(8));
      original->Reset(walk);
      for (int t = 0; t < at; ++t) original->Step(actions[t].data(), walk);
      std::unique_ptr<Env> copy = TossTaskElsewhere(*spec);
      ASSERT_TRUE(copy->Restore(*original->Snapshot()).ok());
      const LockstepRun run = FromSnapshotPoint(*spec, original.get(), copy.get(), actions, at,
                                                at == length, 2, CompareTossTaskVariables);
      ASSERT_EQ(run.difference, "");
      ASSERT_EQ(run.endings.size(), 2u);
      endings.insert(endings.end(), run.endings.begin(), run.endings.end());
    }
    // The windows held the task's own ending: balls caught, balls released.
    EXPECT_GT(Count(endings, task.success), 0);
  }
}

// What a restore that forgot one variable of the task env would leave, noticed through Env
// alone. Not in the list, because TossTaskEnv::Step overwrites them before they are read: the
// world's PD targets (both arms' are set before every world step) and its speeds, palm and ball
// positions "before the last step" (set at the start of every world step).
TEST(EnvSnapshotTest, TossTaskComparisonNoticesAStaleVariable) {
  using S = TossTaskSnapshot;
  struct Case {
    bool throw_task;
    bool at_end;  // snapshot right after the episode's last step (else after step 5)
    StaleVariable stale;
    double action_range = 0.1;  // 0: exact throws, which the throw value judges good
  };
  const std::vector<Case> cases = {
      {true, false, {"rng", Change<S>([](S* s) { s->state.rng = Rng(31337); }), {}}},
      {false, false, {"rng (catch)", Change<S>([](S* s) { s->state.rng = Rng(31337); }), {}}},
      {true, false, {"hand", Change<S>([](S* s) { s->state.hand = Hand::kLeft; }), {}}},
      {true, false, {"mirror", Change<S>([](S* s) { s->state.mirror = -1; }), {}}},
      {false, false, {"mirror (catch)", Change<S>([](S* s) { s->state.mirror = -1; }), {}}},
      {true, false, {"steps", Change<S>([](S* s) { s->state.steps += 1; }), {}}},
      {true, false, {"completions", Change<S>([](S* s) { s->state.completions = 1; }), {}}},
      {true, false, {"throw_value", Change<S>([](S* s) {
                       s->state.throw_value = s->state.throw_value == 3 ? 4 : 3;
                     }), {}}, 0.0},
      {true, false, {"release_step", Change<S>([](S* s) { s->state.release_step += 1; }), {}}},
      {true, false, {"released", Change<S>([](S* s) { s->state.released = true; }), {}}},
      {true, false, {"target_velocity",
                     Change<S>([](S* s) { s->state.target_velocity.z += 0.01; }), {}}},
      {true, true, {"release_velocity_error",
                    Change<S>([](S* s) { s->state.release_velocity_error += 0.5; }), {}}},
      {true, true, {"release_position_error",
                    Change<S>([](S* s) { s->state.release_position_error += 0.5; }), {}}},
      {true, false, {"world: the ball's mode (held)", Change<S>([](S* s) {
                       s->world.balls[0].mode = toss::BallMode::kFree;
                     }), {}}},
      {false, false, {"world: the ball's mode (free, catch)", Change<S>([](S* s) {
                        s->world.balls[0].mode = toss::BallMode::kParked;
                      }), {}}},
      {true, false, {"world: diverged", Change<S>([](S* s) { s->world.diverged = true; }), {}}},
      {true, false, {"qvel alone (positions restored)", {}, [](Env* env) {
                       const auto& world = dynamic_cast<TossTaskEnv&>(*env).world();
                       env->data()->qvel[world.spec().arm(Hand::kRight).dof[1]] += 1e-9;
                     }}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.stale.name);
    const std::shared_ptr<const EnvSpec> spec = TossTaskSpec("toss_base", c.throw_task);
    ASSERT_NE(spec, nullptr);
    const AdaptiveWalk walk(&spec->graph());
    const Actions actions =
        RandomActions(78, 1000, spec->act_dim(), spec->act_dim(), c.action_range);
    std::unique_ptr<Env> original = spec->NewEnv(Rng(8));
    original->Reset(walk);
    int at = 0;
    bool ended = false;
    while (!ended && (at < 5 || c.at_end)) {
      ended = original->Step(actions[at++].data(), walk).outcome != Outcome::kRunning;
    }
    std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
    if (c.stale.in_snapshot) c.stale.in_snapshot(snapshot.get());
    std::unique_ptr<Env> copy = TossTaskElsewhere(*spec);
    ASSERT_TRUE(copy->Restore(*snapshot).ok());
    if (c.stale.in_env) c.stale.in_env(copy.get());
    const LockstepRun run =
        FromSnapshotPoint(*spec, original.get(), copy.get(), actions, at, ended, 2, nullptr);
    EXPECT_NE(run.difference, "") << "a stale " << c.stale.name << " went unnoticed";
    std::printf("  stale %-40s noticed: %s\n", c.stale.name.c_str(), run.difference.c_str());
  }
}

// ---------------------------------------------------------------------------------------------
// The toss in-loop env (envs/toss/loop_env.h) with the base controllers, as trained
// (configs/toss_residual_*.textproto), its runs cut to 6 throws so that runs end and new ones
// start (drawing patterns, transitions and seeds from the env's stream) inside the windows.

std::shared_ptr<const EnvSpec> LoopSpec(const std::string& task) {
  return LoadEditedSpec("toss_residual_" + task, [](config::RunConfig* run) {
    run->mutable_toss()->mutable_loop()->set_max_throws(6);
  });
}

std::unique_ptr<Env> LoopElsewhere(const EnvSpec& spec, const Actions& actions) {
  std::unique_ptr<Env> env = spec.NewEnv(Rng::ForStream(99, 0, 0));
  env->Reset(AdaptiveWalk(&spec.graph()));
  Advance(spec, env.get(), actions, 40);
  return env;
}

// Snapshots at a few points over the first 60 steps (inside segments, at their ends; several
// runs), each restored into a copy that steps with the original through 4 more segment ends
// (each reset advances the runtime through the other arm's and the partner mode's throws and
// catches, and runs end and start anew): positions, velocities, the whole mjData, the runtime's
// mode machines, events and results, the failure bookkeeping, the random stream.
TEST(EnvSnapshotTest, TossLoopCopyFollowsSegmentsAndNewRunsWithVelocitiesAndEveryVariable) {
  for (const char* task : {"catch", "throw"}) {
    SCOPED_TRACE(task);
    const std::shared_ptr<const EnvSpec> spec = LoopSpec(task);
    ASSERT_NE(spec, nullptr);
    const AdaptiveWalk walk(&spec->graph());
    const Actions actions = RandomActions(79, 2000, spec->act_dim(), spec->act_dim(), 0.3);
    std::vector<Outcome> endings;
    int runs = 0;
    for (const int at : {0, 5, 17, 31, 60}) {
      SCOPED_TRACE(absl::StrCat("restored after step ", at));
      std::unique_ptr<Env> original = spec->NewEnv(Rng::ForStream(4, 0, 0));
      original->Reset(walk);
      Advance(*spec, original.get(), actions, at);
      std::unique_ptr<Env> copy = LoopElsewhere(*spec, actions);
      ASSERT_TRUE(copy->Restore(*original->Snapshot()).ok());
      const int runs_before = dynamic_cast<TossLoopEnv&>(*original).runs_started();
      const LockstepRun run = StepInLockstep(*spec, original.get(), copy.get(), actions, at,
                                             1000, 4, CompareLoopVariables);
      ASSERT_EQ(run.difference, "");
      ASSERT_EQ(run.endings.size(), 4u);
      endings.insert(endings.end(), run.endings.begin(), run.endings.end());
      runs += dynamic_cast<TossLoopEnv&>(*original).runs_started() - runs_before;
    }
    EXPECT_GT(Count(endings, std::string(task) == "catch" ? toss::kCaught : toss::kReleased), 0);
    EXPECT_GT(runs, 0) << "no new run started inside a window";
  }
}

// What a restore that forgot one variable of the loop env would leave, noticed through Env
// alone. The runtime's own variables are copied whole by TossJuggler::Clone (its copy
// constructor); a stale world or physics inside it is noticed as below. Not in the list:
// runs_started (a count for tests that nothing steps by) and run_pattern (it only moves the
// failure rate of a run that fails, and these runs do not).
TEST(EnvSnapshotTest, TossLoopComparisonNoticesAStaleVariable) {
  using S = TossLoopSnapshot;
  // The runtime inside the snapshot, changed through a copy of it.
  auto change_world = [](std::function<void(TossWorld::Snapshot*)> f) {
    return Change<S>([f](S* s) {
      std::unique_ptr<TossJuggler> juggler = s->juggler->Clone();
      TossWorld::Snapshot w;
      juggler->world().Save(&w);
      f(&w);
      juggler->mutable_world()->Restore(w);
      s->juggler = std::move(juggler);
    });
  };
  const std::vector<StaleVariable> cases = {
      {"rng", Change<S>([](S* s) { s->rng = Rng(31337); }), {}},
      {"steps", Change<S>([](S* s) { s->steps += 1; }), {}},
      {"completions", Change<S>([](S* s) { s->completions = 1; }), {}},
      {"failure_rate", Change<S>([](S* s) { s->failure_rate[0] = 50; }), {}},
      {"juggler: a held ball's mode", change_world([](TossWorld::Snapshot* w) {
         for (auto& ball : w->balls) {
           if (ball.mode == toss::BallMode::kHeld) {
             ball.mode = toss::BallMode::kFree;
             break;
           }
         }
       }),
       {}},
      {"juggler: diverged", change_world([](TossWorld::Snapshot* w) { w->diverged = true; }), {}},
      {"qvel alone (positions restored)", {}, [](Env* env) {
         const auto& world = dynamic_cast<TossLoopEnv&>(*env).juggler().world();
         env->data()->qvel[world.spec().arm(Hand::kRight).dof[1]] += 1e-9;
       }},
  };
  const std::shared_ptr<const EnvSpec> spec = LoopSpec("catch");
  ASSERT_NE(spec, nullptr);
  const AdaptiveWalk walk(&spec->graph());
  const Actions actions = RandomActions(79, 2000, spec->act_dim(), spec->act_dim(), 0.3);
  for (const StaleVariable& stale : cases) {
    SCOPED_TRACE(stale.name);
    std::unique_ptr<Env> original = spec->NewEnv(Rng::ForStream(4, 0, 0));
    original->Reset(walk);
    Advance(*spec, original.get(), actions, 3);
    std::unique_ptr<EnvSnapshot> snapshot = original->Snapshot();
    if (stale.in_snapshot) stale.in_snapshot(snapshot.get());
    std::unique_ptr<Env> copy = LoopElsewhere(*spec, actions);
    ASSERT_TRUE(copy->Restore(*snapshot).ok());
    if (stale.in_env) stale.in_env(copy.get());
    const LockstepRun run =
        StepInLockstep(*spec, original.get(), copy.get(), actions, 3, 1000, 6, nullptr);
    EXPECT_NE(run.difference, "") << "a stale " << stale.name << " went unnoticed";
    std::printf("  stale %-40s noticed: %s\n", stale.name.c_str(), run.difference.c_str());
  }
}

// ---------------------------------------------------------------------------------------------
// Refusals.

TEST(EnvSnapshotTest, RefusesASnapshotOfAnotherFamily) {
  const std::shared_ptr<const EnvSpec> soccer = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> toss = LoadFamilySpec("toss_catch");
  ASSERT_NE(soccer, nullptr);
  ASSERT_NE(toss, nullptr);
  const AdaptiveWalk soccer_walk(&soccer->graph()), toss_walk(&toss->graph());
  std::unique_ptr<Env> soccer_env = soccer->NewEnv(Rng(1));
  std::unique_ptr<Env> toss_env = toss->NewEnv(Rng(1));
  soccer_env->Reset(soccer_walk);
  toss_env->Reset(toss_walk);
  PhysicsSnapshot before;
  before.Save(soccer->model(), soccer_env->data());
  const absl::Status s = soccer_env->Restore(*toss_env->Snapshot());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message(), "a snapshot of a toss env cannot be restored into a soccer_juggle env");
  EXPECT_TRUE(before.Equals(soccer_env->data())) << "a refused restore changed the env";
  const absl::Status t = toss_env->Restore(*soccer_env->Snapshot());
  EXPECT_EQ(t.code(), absl::StatusCode::kInvalidArgument);
}

TEST(EnvSnapshotTest, RefusesASnapshotOfAnotherModelOrConfig) {
  // Same family, another config (the paper's reference without the base controller).
  const std::shared_ptr<const EnvSpec> recipe = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> paper = LoadFamilySpec("right_foot_paper");
  ASSERT_NE(recipe, nullptr);
  ASSERT_NE(paper, nullptr);
  EXPECT_NE(recipe->fingerprint(), paper->fingerprint());
  const AdaptiveWalk walk(&recipe->graph());
  std::unique_ptr<Env> a = recipe->NewEnv(Rng(1));
  std::unique_ptr<Env> b = paper->NewEnv(Rng(1));
  a->Reset(walk);
  b->Reset(AdaptiveWalk(&paper->graph()));
  const absl::Status s = a->Restore(*b->Snapshot());
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("another model or config"), std::string::npos) << s;
  // Two specs built from the same config are equal: their snapshots are interchangeable.
  const std::shared_ptr<const EnvSpec> recipe_again = LoadFamilySpec("right_foot_recipe");
  EXPECT_EQ(recipe->fingerprint(), recipe_again->fingerprint());
  std::unique_ptr<Env> c = recipe_again->NewEnv(Rng(2));
  EXPECT_TRUE(c->Restore(*a->Snapshot()).ok());
}

TEST(EnvSnapshotTest, DifferentModelsHaveDifferentFingerprints) {
  const std::shared_ptr<const EnvSpec> soccer = LoadFamilySpec("right_foot_recipe");
  const std::shared_ptr<const EnvSpec> toss = LoadFamilySpec("toss_catch");
  ASSERT_NE(soccer, nullptr);
  ASSERT_NE(toss, nullptr);
  EXPECT_NE(ModelFingerprint(soccer->model()), ModelFingerprint(toss->model()));
  EXPECT_EQ(ModelFingerprint(soccer->model()), ModelFingerprint(soccer->model()));
}

}  // namespace
}  // namespace juggle
