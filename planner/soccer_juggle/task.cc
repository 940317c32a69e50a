#include "planner/soccer_juggle/task.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "common/check.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {

using soccer_juggle::JuggleEnv;

SoccerJuggleTask::SoccerJuggleTask(std::shared_ptr<const soccer_juggle::JuggleSpec> spec,
                                   const config::PlannerConfig& config)
    : spec_(std::move(spec)),
      settings_(config.soccer_juggle()),
      run_on_every_kick_(config.run_on_every_kick()),
      layout_(MakeSoccerPlanLayout(config, settings_.kick())),
      space_(MakeSoccerSearchSpace(layout_, config, settings_.kick())) {
  rescue_space_ = space_;
  if (config.rescue().body()) {
    // The regular search keeps the body knots of its warm start.
    std::fill(space_.sigma.begin() + layout_.kick_dim(), space_.sigma.end(), 0.0);
  }
  for (int v = 0; v < rescue_space_.dim(); ++v) {
    rescue_space_.sigma[v] = std::min(rescue_space_.sigma[v] * config.rescue().sigma_scale(),
                                      rescue_space_.upper[v] - rescue_space_.lower[v]);
  }
  if (settings_.has_kick_memory() && layout_.kick_sets > 0) {
    absl::StatusOr<KickMemory> memory =
        KickMemory::Load(settings_.kick_memory().file(), settings_.cost());
    JUGGLE_CHECK(memory.ok(), "the kick memory was checked by ValidateSoccerJuggleTask");
    memory_ = *std::move(memory);
  }
}

int SoccerJuggleTask::KnotAtOrBefore(int step) const {
  return planner::KnotAtOrBefore(layout_, step);
}

bool SoccerJuggleTask::StartsCycle(const Env&, int node) const {
  return spec_->graph().node(node).stage == config::DOWN;
}

std::vector<double> SoccerJuggleTask::Shift(const std::vector<double>& theta, int grid_steps,
                                            int cycles) const {
  const int knots = layout_.knot_steps > 0 ? grid_steps / layout_.knot_steps : 0;
  return ShiftSoccerPlan(layout_, theta, knots, cycles);
}

std::vector<std::vector<double>> SoccerJuggleTask::Seeds(const std::vector<double>& start) const {
  // The warm start, and the same with the nominal kick (a carried kick that no longer fits is
  // then one candidate away from the configured swing).
  std::vector<std::vector<double>> seeds = {start};
  if (layout_.kick_sets > 0) {
    seeds.push_back(start);
    std::fill(seeds.back().begin(), seeds.back().begin() + layout_.kick_dim(), 0.0);
  }
  return seeds;
}

bool SoccerJuggleTask::Released(const Env& env) {
  const auto& juggle = static_cast<const JuggleEnv&>(env);
  const auto& s = juggle.state();
  return s.kick_touched && !s.touched_this_step && !InStall(juggle);
}

void SoccerJuggleTask::Restrict(const Env& env, const std::vector<double>& shifted,
                                SearchSpace* space,
                                std::vector<std::vector<double>>* seeds) const {
  if (memory_.has_value()) AddRememberedKicks(env, seeds);
  if (layout_.hold_follow_through) HoldFollowThrough(env, shifted, space, seeds);
  // After the current cycle's release its kick set is held where it is.
  if (!(settings_.kick().freeze_after_release() && Released(env) && layout_.kick_sets > 0)) return;
  for (int v = 0; v < kKickVariables; ++v) {
    space->lower[v] = space->upper[v] = shifted[v];
    space->sigma[v] = 0;
  }
  for (std::vector<double>& seed : *seeds) {
    std::copy_n(shifted.begin(), kKickVariables, seed.begin());
  }
}

void SoccerJuggleTask::HoldFollowThrough(const Env& env, const std::vector<double>& shifted,
                                         SearchSpace* space,
                                         std::vector<std::vector<double>>* seeds) const {
  // Released now: this re-plan's count since the release, and once it passes hold_after the
  // kick the previous plan left with (its first set then, or the hold it already had); else
  // nothing held. Every candidate carries the same values.
  double held[kKickVariables + 1] = {0};
  if (Released(env)) {
    const double count = shifted[layout_.held_count()] + 1;
    const bool had = shifted[layout_.held_count()] > layout_.hold_after;
    if (count > layout_.hold_after) {
      std::copy_n(shifted.begin() + (had ? layout_.held() : layout_.kick(0)), kKickVariables, held);
    }
    held[kKickVariables] = count;
  }
  FixHeld(held, space, seeds);
}

bool SoccerJuggleTask::RestrictRescue(const Env& env, const std::vector<double>& shifted,
                                      SearchSpace* space,
                                      std::vector<std::vector<double>>* seeds) const {
  if (!layout_.hold_in_rescue || !Released(env)) return false;
  if (space->lower[layout_.held_count()] > layout_.hold_after) return false;  // held already
  // The way back plays the previous plan's set now; a count past hold_after keeps the hold on.
  double held[kKickVariables + 1];
  std::copy_n(shifted.begin() + layout_.kick(0), kKickVariables, held);
  held[kKickVariables] = layout_.hold_after + 1;
  FixHeld(held, space, seeds);
  return true;
}

void SoccerJuggleTask::FixHeld(const double* held, SearchSpace* space,
                               std::vector<std::vector<double>>* seeds) const {
  for (int i = 0; i <= kKickVariables; ++i) {
    const int v = layout_.held() + i;
    space->lower[v] = space->upper[v] = held[i];
    space->sigma[v] = 0;
    for (std::vector<double>& seed : *seeds) seed[v] = held[i];
  }
}

bool SoccerJuggleTask::PlanActs(const Env& env, const double* theta, PlanClock clock) const {
  if (layout_.body_knots > 0) return true;
  if (layout_.follows_held(theta, clock.cycle)) return false;
  if (layout_.kick_ramp(static_cast<const JuggleEnv&>(env).cursor().phase) == 0) return false;
  return layout_.acting_kick_set(clock.cycle) >= 0;
}

void SoccerJuggleTask::AddRememberedKicks(const Env& env,
                                          std::vector<std::vector<double>>* seeds) const {
  const std::optional<KickContext> context =
      KickContextOf(static_cast<const JuggleEnv&>(env));
  const std::optional<VariableBlock> next = RefineBlock(env);  // the next kick's set
  if (!context.has_value() || !next.has_value()) return;
  const std::vector<double> start = seeds->front();
  for (const KickDecision& kick : memory_->Nearest(*context, settings_.kick_memory().neighbours())) {
    std::vector<double> seed = start;
    for (int v = 0; v < kKickVariables; ++v) {
      const int i = next->first + v;
      seed[i] = std::clamp(kick[v], space_.lower[i], space_.upper[i]);
    }
    seeds->push_back(std::move(seed));
  }
}

double SoccerJuggleTask::ContactClearance(const Env& env) const {
  return BallClearance(static_cast<const JuggleEnv&>(env));
}

double SoccerJuggleTask::PlanCost(const double* theta, const std::vector<double>& warm,
                                  bool has_warm) const {
  // Kick consistency with the warm start and the kick prior (PlannerCost.kick_consistency,
  // kick_prior), in units of the search spreads.
  const double consistency = has_warm ? settings_.cost().kick_consistency() : 0;
  const double prior = settings_.cost().kick_prior();
  if (consistency <= 0 && prior <= 0) return 0;
  double sum = 0;
  for (int v = 0; v < layout_.kick_dim(); ++v) {
    if (space_.sigma[v] <= 0) continue;
    sum += consistency * std::pow((theta[v] - warm[v]) / space_.sigma[v], 2) +
           prior * std::pow(theta[v] / space_.sigma[v], 2);
  }
  return sum;
}

void SoccerJuggleTask::Action(const Env& env, const double* theta, PlanClock clock,
                              const double* prior, float* action) const {
  SoccerPlanAction(static_cast<const JuggleEnv&>(env), layout_, theta, clock, action, prior);
}

std::unique_ptr<RolloutScorer> SoccerJuggleTask::NewScorer() const {
  return std::make_unique<SoccerRolloutScorer>(settings_.cost(), layout_.horizon,
                                               run_on_every_kick_);
}

std::vector<std::string> SoccerJuggleTask::term_names() const { return SoccerTermNames(); }
std::vector<std::string> SoccerJuggleTask::outcome_names() const { return KickOutcomeNames(); }

VariableBlock SoccerJuggleTask::KickBlock(int set) const {
  return {layout_.kick(set), KickRefineSteps()};
}

std::optional<VariableBlock> SoccerJuggleTask::RefineBlock(const Env& env) const {
  if (layout_.kick_sets == 0) return std::nullopt;
  // The set of the next kick inside the horizon (not a held one).
  const bool touched = static_cast<const JuggleEnv&>(env).state().kick_touched;
  const int set = std::min(touched ? 1 : 0, layout_.kick_sets - 1);
  if (set == 0 && Released(env) && settings_.kick().freeze_after_release()) return std::nullopt;
  return KickBlock(set);
}

bool SoccerJuggleTask::Residuals(const std::vector<double>& outcome, double* out) const {
  const KickOutcome k = KickOutcomeOf(outcome);
  if (!k.valid) return false;
  const config::PlannerCost& w = settings_.cost();
  out[0] = k.timing / w.timing_scale_s();
  out[1] = k.dx / w.landing_scale();
  out[2] = k.dy / w.landing_scale();
  return true;
}

double SoccerJuggleTask::refine_prior_weight() const {
  const config::PlannerCost& w = settings_.cost();
  return w.kick() > 0 ? w.kick_prior() / w.kick() : 0;
}

std::optional<VariableBlock> SoccerJuggleTask::ActingBlock(PlanClock clock) const {
  const int set = layout_.acting_kick_set(clock.cycle);
  if (set < 0) return std::nullopt;
  return KickBlock(set);
}

const float* SoccerJuggleTask::AppliedAction(const Env& env) const {
  return static_cast<const JuggleEnv&>(env).state().previous_action.data();
}

int SoccerJuggleTask::decision_size() const {
  return std::min(kKickVariables, layout_.kick_dim());
}

std::string SoccerJuggleTask::DescribeDecision(const std::vector<double>& d,
                                               const std::vector<double>& outcome) const {
  std::string out = FormatKickVariables(d);
  const KickOutcome k = KickOutcomeOf(outcome);
  if (k.valid) {
    absl::StrAppendFormat(&out, "  kick: timing %+.0f ms, landing %+.3f %+.3f m, apex %+.3f m",
                          k.timing * 1000, k.dx, k.dy, k.apex);
    if (std::isfinite(k.impact_acceleration)) {
      absl::StrAppendFormat(&out, ", impact %+.1f m/s^2", k.impact_acceleration);
    }
  }
  return out;
}

namespace {

// What a node's kick variables move: the leg swing's amplitudes, the header set, or the
// declared joint axes (plan.cc KickReferences); equal strings move the same joints alike.
std::string KickVariablesMeaning(const config::NodeSpec& node) {
  if (node.kick_variable_size() == 0) {
    return node.pose().has_leg_swing() ? "leg swing" : "header or chest";
  }
  std::string out = "declared";
  for (const config::KickVariableSpec& v : node.kick_variable()) {
    out += "|";
    for (const config::JointAxis& m : v.move()) {
      absl::StrAppend(&out, m.joint(), ":", m.axis(), "*", m.gain(), " ");
    }
  }
  return out;
}

std::string KickVariablesKind(const config::NodeSpec& node) {
  if (node.kick_variable_size() > 0) return "declared kick variables";
  return node.pose().has_leg_swing() ? "a leg swing" : "a header or chest";
}

}  // namespace

absl::Status ValidateSoccerJuggleTask(const LoadedConfig& config) {
  const config::PlannerConfig& p = config.run.planner();
  auto where = [&](const char* field) { return config.root.Where({{"planner"}, {field}}); };
  const int episode = config.run.soccer_juggle().env().max_episode_steps();
  if (p.horizon_steps() > episode) {
    return absl::InvalidArgumentError(absl::StrCat(
        where("horizon_steps"), ": a horizon of ", p.horizon_steps(),
        " control steps is longer than the episode (soccer_juggle.env.max_episode_steps ",
        episode, ")"));
  }
  if (absl::StatusOr<std::vector<int>> a = BodyActionIndices(p.body_actions()); !a.ok()) {
    return absl::InvalidArgumentError(absl::StrCat(where("body_actions"), ": ", a.status().message()));
  }
  // Nodes the search has nothing to steer with or nothing to score.
  if (config.graph != nullptr) {
    const ControlGraph& graph = *config.graph;
    for (int n = 0; n < graph.num_nodes(); ++n) {
      const GraphNode& node = graph.node(n);
      if (node.spec.pose().has_keyframes() && node.spec.kick_variable_size() == 0) {
        return absl::InvalidArgumentError(absl::StrCat(
            config.graph_locator.Where({{"node", n}, {"pose"}, {"keyframes"}}), ": node '",
            node.name, "' moves by keyframes: declare the joints its kick variables move "
            "(kick_variable { move { joint: ... } }); the header set would steer its kick with "
            "the chest and the neck"));
      }
    }
  }
  // One kick set serves every cycle in the horizon (unless later cycles kick by the base
  // controller): the set of a node whose variables move other joints than the next node's (a
  // leg swing's amplitudes read as a header's chest and neck) would steer the wrong kick.
  const config::KickVariables& kick = p.soccer_juggle().kick();
  if (kick.enabled() && kick.cycles() < 2 && !kick.later_kicks_by_base() &&
      config.graph != nullptr) {
    const ControlGraph& graph = *config.graph;
    for (int e = 0; e < graph.num_edges(); ++e) {
      const GraphNode& from = graph.node(graph.edge(e).from);
      const GraphNode& to = graph.node(graph.edge(e).to);
      if (from.stage != config::UP) continue;
      if (KickVariablesMeaning(from.spec) == KickVariablesMeaning(to.spec)) continue;
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where({{"planner"}, {"soccer_juggle"}, {"kick"}, {"cycles"}}), ": ",
          kick.cycles(), " kick variable set for a graph whose edge ", from.name, " -> ", to.name,
          " leads from ", KickVariablesKind(from.spec), " to ", KickVariablesKind(to.spec),
          ": their variables move different joints; set cycles: 2 or more"));
    }
  }
  for (int i = 0; i < kick.held_angles_size(); ++i) {
    if (kick.held_angles(i) < 1 || kick.held_angles(i) >= kKickVariables) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where({{"planner"}, {"soccer_juggle"}, {"kick"}, {"held_angles", i}}),
          ": ", kick.held_angles(i), " is not an angle variable's position (1 hip, 2 abduction, "
          "3 knee, 4 ankle, or a node's first to fourth declared variable)"));
    }
  }
  if (kick.hold_in_rescue() && !kick.hold_follow_through()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"soccer_juggle"}, {"kick"}, {"hold_in_rescue"}}),
        ": a rescue's hold, and hold_follow_through is false: nothing is held; set "
        "hold_follow_through: true or remove the field"));
  }
  if (kick.hold_after_replans() > 0 && !kick.hold_follow_through()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"soccer_juggle"}, {"kick"}, {"hold_after_replans"}}),
        ": ", kick.hold_after_replans(), " re-plans before a hold, and hold_follow_through is "
        "false: nothing is held; set hold_follow_through: true or remove the field"));
  }
  if (p.soccer_juggle().has_kick_memory()) {
    const config::KickMemoryConfig& memory = p.soccer_juggle().kick_memory();
    const std::string where_file = config.root.Where(
        {{"planner"}, {"soccer_juggle"}, {"kick_memory"}, {"file"}});
    if (!kick.enabled()) {
      return absl::InvalidArgumentError(absl::StrCat(
          where_file, ": kick_memory.file: a kick memory proposes kick variables, and "
          "kick.enabled is false"));
    }
    if (absl::StatusOr<KickMemory> m = KickMemory::Load(memory.file(), p.soccer_juggle().cost());
        !m.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(where_file, ": kick_memory.file: ",
                                                     m.status().message()));
    }
    // A search's first iteration holds its seeds (planner/cem_search.h): the warm start, the
    // nominal kick, the remembered kicks and, in a rescue, the troubled best before them.
    // MinimizeCem drops seeds that do not fit, so too many neighbours would be ignored.
    const int seeds = 2 + memory.neighbours();
    const int rescue_samples = p.rescue().narrowed_samples() > 0
                                   ? std::min(p.rescue().samples(), p.rescue().narrowed_samples())
                                   : p.rescue().samples();
    const bool regular = seeds > p.samples();
    if (regular || (p.rescue().cost_above() > 0 && seeds + 1 > rescue_samples)) {
      return absl::InvalidArgumentError(absl::StrCat(
          config.root.Where({{"planner"}, {"soccer_juggle"}, {"kick_memory"}, {"neighbours"}}),
          ": ", memory.neighbours(), " remembered kicks with the warm start and the nominal kick",
          regular ? " are " : " and the troubled plan are ", regular ? seeds : seeds + 1,
          " seeds, more than the ",
          regular ? absl::StrCat(p.samples(), " samples of planner.samples")
                  : absl::StrCat(rescue_samples, " samples of the rescue's first iteration"),
          "; the rest would be dropped: lower neighbours or raise the samples"));
    }
  }
  if (!kick.enabled() && (p.refine_iterations() > 0 || p.rescue().refine_first() > 0 ||
                          p.rescue().refine_after() > 0)) {
    // The refinement steps on a kick's variables (RefineBlock); without them nothing refines.
    const char* rescue_field = p.rescue().refine_first() > 0 ? "refine_first" : "refine_after";
    return absl::InvalidArgumentError(absl::StrCat(
        p.refine_iterations() > 0
            ? where("refine_iterations")
            : config.root.Where({{"planner"}, {"rescue"}, {rescue_field}}),
        ": the refinement steps on the kick variables, and soccer_juggle.kick.enabled is false; "
        "set it to 0"));
  }
  const config::PlannerCost& cost = p.soccer_juggle().cost();
  if (cost.impact_acceleration_min() > cost.impact_acceleration_max()) {
    return absl::InvalidArgumentError(absl::StrCat(
        config.root.Where({{"planner"}, {"soccer_juggle"}, {"cost"}, {"impact_acceleration_min"}}),
        ": ", cost.impact_acceleration_min(), " m/s^2 is above impact_acceleration_max (",
        cost.impact_acceleration_max(), "): the band is empty"));
  }
  return absl::OkStatus();
}

}  // namespace juggle::planner
