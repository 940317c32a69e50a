// Planner settings: out-of-range values are config errors naming file, line and field; the
// planner refuses settings the schema allows but the run does not.
#include <string>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "envs/registry.h"
#include "envs/testing/test_configs.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "planner/planner_config.h"
#include "planner/planner_controller.h"
#include "planner/soccer_juggle/plan.h"

namespace juggle::planner {
namespace {

using ::juggle::testing::RepoPath;
using ::juggle::testing::WriteTemp;
using ::testing::HasSubstr;
using ::testing::StartsWith;

// A config over `base` (a shipped config) with `planner_fields` in its planner block.
std::string ConfigOver(const std::string& base, const std::string& planner_fields) {
  return absl::StrCat("base_config: \"", RepoPath(base), "\"\nplanner {\n  ", planner_fields,
                      "\n}\n");
}

// The same over the shipped right-foot planner config.
std::string Config(const std::string& planner_fields) {
  return ConfigOver("configs/right_foot_planner.textproto", planner_fields);
}

absl::Status Load(const std::string& name, const std::string& text,
                  LoadedConfig* out = nullptr) {
  const std::string path = WriteTemp(name, text);
  absl::StatusOr<LoadedConfig> loaded = LoadRunConfig(path);
  if (!loaded.ok()) return loaded.status();
  if (out != nullptr) *out = *loaded;
  return absl::OkStatus();
}

TEST(PlannerConfigTest, ZeroSamplesIsAnErrorNamingFileLineAndField) {
  const std::string text = Config("samples: 0");
  const absl::Status s = Load("zero_samples.textproto", text);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(WriteTemp("zero_samples.textproto", text), text,
                                                "samples: 0")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("planner.samples"));
}

TEST(PlannerConfigTest, NegativeHorizonIsAnErrorNamingTheField) {
  const absl::Status s = Load("negative_horizon.textproto", Config("horizon_steps: -5"));
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), HasSubstr("planner.horizon_steps"));
}

TEST(PlannerConfigTest, ARescueSearchTooSmallForItsSeedsIsAnErrorNamingTheField) {
  // The rescue starts from three plans (the best found, the warm start, the nominal kick).
  const absl::Status s = Load("rescue.textproto", Config("rescue { cost_above: 500 samples: 2 }"));
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), HasSubstr("planner.rescue.samples"));
}

TEST(PlannerConfigTest, ARescueOfBodyKnotsWithoutBodyKnotsIsRefused) {
  const std::string text = Config("body_knot_steps: 0 rescue { cost_above: 500 body: true }");
  LoadedConfig config;
  ASSERT_TRUE(Load("rescue_body.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "body: true")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("body_knot_steps is 0"));
}

TEST(PlannerConfigTest, AHoldAfterReplansWithoutAHeldFollowThroughIsRefusedAtTheField) {
  const std::string text =
      Config("soccer_juggle { kick { hold_after_replans: 2 } }");
  LoadedConfig config;
  ASSERT_TRUE(Load("hold_after.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "hold_after_replans: 2")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("hold_follow_through is false"));
  ASSERT_TRUE(Load("hold_after_ok.textproto",
                   Config("soccer_juggle { kick { hold_follow_through: true hold_after_replans: 2 } }"),
                   &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
}

TEST(PlannerConfigTest, ARescuesHoldWithoutAHeldFollowThroughIsRefusedAtTheField) {
  const std::string text = Config("soccer_juggle { kick { hold_in_rescue: true } }");
  LoadedConfig config;
  ASSERT_TRUE(Load("hold_in_rescue.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "hold_in_rescue: true")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("hold_follow_through is false"));
  ASSERT_TRUE(
      Load("hold_in_rescue_ok.textproto",
           Config("soccer_juggle { kick { hold_follow_through: true hold_in_rescue: true } }"),
           &config)
          .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
}

TEST(PlannerConfigTest, AHeldAngleOutsideTheFourAngleVariablesIsRefusedAtTheField) {
  const std::string text = Config("soccer_juggle { kick { held_angles: 0 } }");
  LoadedConfig config;
  ASSERT_TRUE(Load("held_angles.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "held_angles: 0")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("not an angle variable's position"));
  ASSERT_TRUE(Load("held_angles_5.textproto", Config("soccer_juggle { kick { held_angles: 5 } }"),
                   &config)
                  .ok());
  EXPECT_FALSE(ValidatePlannerConfig(config).ok());
  ASSERT_TRUE(Load("held_angles_ok.textproto",
                   Config("soccer_juggle { kick { held_angles: [3, 4] } }"), &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
}

TEST(PlannerConfigTest, ARescueStoppingAboveItsTroubleThresholdIsRefusedAtTheField) {
  const std::string text = Config("rescue { cost_above: 500 stop_below: 600 }");
  LoadedConfig config;
  ASSERT_TRUE(Load("rescue_stop.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "stop_below: 600")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("cost_above is 500"));
  ASSERT_TRUE(
      Load("rescue_stop_ok.textproto", Config("rescue { cost_above: 500 stop_below: 100 }"), &config)
          .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
}

TEST(PlannerConfigTest, ATrustInTheProposalWithoutAPolicyPriorIsRefusedAtTheField) {
  const std::string text = Config("search_prior_trust: true");
  LoadedConfig config;
  ASSERT_TRUE(Load("trust.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "search_prior_trust")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("needs planner.policy_prior: true"));
  LoadedConfig with_prior;
  ASSERT_TRUE(Load("trust_prior.textproto",
                   Config("search_prior_trust: true policy_prior: true"), &with_prior).ok());
  EXPECT_TRUE(ValidatePlannerConfig(with_prior).ok());
}

TEST(PlannerConfigTest, AHorizonLongerThanTheEpisodeIsRefused) {
  const std::string text = Config("horizon_steps: 5000");
  LoadedConfig config;
  const absl::Status loaded = Load("long_horizon.textproto", text, &config);
  ASSERT_TRUE(loaded.ok()) << loaded;
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "horizon_steps")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("longer than the episode"));
}

TEST(PlannerConfigTest, ReplanningBeyondTheHorizonIsRefused) {
  LoadedConfig config;
  ASSERT_TRUE(Load("replan.textproto", Config("horizon_steps: 10 replan_every: 11"), &config).ok());
  EXPECT_THAT(std::string(ValidatePlannerConfig(config).message()),
              HasSubstr("planner.replan_every"));
}

TEST(PlannerConfigTest, AnEmptyImpactAccelerationBandIsRefused) {
  LoadedConfig config;
  ASSERT_TRUE(Load("band.textproto",
                   Config("soccer_juggle { cost { impact_acceleration_min: -2 "
                          "impact_acceleration_max: -3 } }"),
                   &config).ok());
  EXPECT_THAT(std::string(ValidatePlannerConfig(config).message()),
              HasSubstr("planner.soccer_juggle.cost.impact_acceleration_min"));
  ASSERT_TRUE(Load("band.textproto",
                   Config("soccer_juggle { cost { impact_acceleration_min: -3 "
                          "impact_acceleration_max: -3 } }"),
                   &config).ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
}

TEST(PlannerConfigTest, BodyActionsNameJointsAndAxesOfTheCharacter) {
  LoadedConfig config;
  ASSERT_TRUE(Load("bad_joint.textproto", Config("body_actions: \"left_toe\""), &config).ok());
  EXPECT_THAT(std::string(ValidatePlannerConfig(config).message()),
              HasSubstr("planner.body_actions: 'left_toe' names no joint"));
  ASSERT_TRUE(Load("bad_axis.textproto", Config("body_actions: \"left_knee:x\""), &config).ok());
  EXPECT_THAT(std::string(ValidatePlannerConfig(config).message()),
              HasSubstr("an axis (x, y or z) of a ball joint"));
  google::protobuf::RepeatedPtrField<std::string> names;
  *names.Add() = "left_ankle:x";
  *names.Add() = "left_knee";
  *names.Add() = "chest";
  // left_ankle is the last ball joint (actions 25..27), left_knee the hinge before it (24).
  EXPECT_EQ(*BodyActionIndices(names), (std::vector<int>{25, 24, 0, 1, 2}));
  EXPECT_EQ(BodyActionIndices({})->size(), 28u);
}

TEST(PlannerConfigTest, OneKickSetRepeatedForAGraphMixingKicksAndHeadersIsRefusedAtTheField) {
  // configs/foot_and_head_planner.textproto with the kick sets of the right-foot planner.
  const std::string text = absl::StrCat(
      "base_config: \"", RepoPath("configs/foot_and_head_planner.textproto"),
      "\"\nplanner { soccer_juggle { kick { cycles: 1 } } }\n");
  LoadedConfig config;
  ASSERT_TRUE(Load("one_set.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), HasSubstr("planner.soccer_juggle.kick.cycles"));
  EXPECT_THAT(std::string(s.message()), HasSubstr("right_foot_up -> head_down"));
  // With the later cycles kicked by the base controller, the one set serves only its own cycle.
  ASSERT_TRUE(Load("one_set_base.textproto",
                   ConfigOver("configs/foot_and_head_planner.textproto",
                              "soccer_juggle { kick { cycles: 1 later_kicks_by_base: true } }"),
                   &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);

  absl::StatusOr<LoadedConfig> shipped =
      LoadRunConfig(RepoPath("configs/foot_and_head_planner.textproto"));
  ASSERT_TRUE(shipped.ok()) << shipped.status();
  EXPECT_TRUE(ValidatePlannerConfig(*shipped).ok()) << ValidatePlannerConfig(*shipped);
}

TEST(PlannerConfigTest, TheShippedPlannerConfigIsValid) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(RepoPath("configs/right_foot_planner.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  EXPECT_TRUE(ValidatePlannerConfig(*config).ok());
}

TEST(PlannerConfigTest, ARefinementForATaskWithoutOneIsRefusedAtTheField) {
  for (const char* field :
       {"refine_iterations: 2", "rescue { refine_first: 2 }", "rescue { refine_after: 2 }"}) {
    const std::string text = ConfigOver("configs/toss_throw_planner.textproto", field);
    LoadedConfig config;
    ASSERT_TRUE(Load("toss_refine.textproto", text, &config).ok());
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << field;
    const std::string at = absl::StrContains(field, "refine_first")   ? "refine_first: 2"
                           : absl::StrContains(field, "refine_after") ? "refine_after: 2"
                                                                      : field;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, at)));
    EXPECT_THAT(std::string(s.message()), HasSubstr("the toss planning task has no refinement"));
  }
  // The soccer task refines its kick variables, not without them.
  const std::string no_kick = Config(
      "body_knot_steps: 5 soccer_juggle { kick { enabled: false } } rescue { refine_first: 1 }");
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_no_kick_refine.textproto", no_kick, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, no_kick, "refine_first: 1")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("kick.enabled is false"));
  const std::string no_kick_after = Config(
      "body_knot_steps: 5 soccer_juggle { kick { enabled: false } } rescue { refine_after: 1 }");
  ASSERT_TRUE(Load("soccer_no_kick_refine_after.textproto", no_kick_after, &config).ok());
  EXPECT_THAT(std::string(ValidatePlannerConfig(config).message()),
              StartsWith(::juggle::testing::Loc(config.config_path, no_kick_after,
                                                "refine_after: 1")));
  ASSERT_TRUE(Load("soccer_refine.textproto",
                   Config("refine_iterations: 2 rescue { refine_first: 2 }"), &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, ARescueIgnoringLaterKicksForATaskWithoutThemIsRefusedAtTheField) {
  const std::string text =
      ConfigOver("configs/toss_throw_planner.textproto", "rescue { ignore_later_kicks: true }");
  LoadedConfig config;
  ASSERT_TRUE(Load("toss_later.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text,
                                                "ignore_later_kicks: true")));
  EXPECT_THAT(std::string(s.message()), HasSubstr("the toss planning task's cost has no later"));
  // The soccer task has them.
  ASSERT_TRUE(
      Load("soccer_later.textproto", Config("rescue { ignore_later_kicks: true }"), &config).ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, AHalfFixedBarNotBelowTheRescuesCostAboveIsRefusedAtTheField) {
  // The shipped config's rescue runs above 500.
  for (const char* field : {"half_fixed_above: 500", "half_fixed_above: 800"}) {
    const std::string text = Config(absl::StrCat("rescue { ", field, " }"));
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_half_fixed.textproto", text, &config).ok());
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << field;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, field)));
    EXPECT_THAT(std::string(s.message()), HasSubstr("cost_above (500)"));
  }
  LoadedConfig config;
  ASSERT_TRUE(
      Load("soccer_half_fixed.textproto", Config("rescue { half_fixed_above: 150 }"), &config).ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, LightReplansNeedBothFieldsABarBelowTheRescueAWindowAndNoColdStart) {
  // Each case: the fields, the field the error names, what it says.
  const struct {
    const char* fields;
    const char* named;
    const char* says;
  } cases[] = {
      {"search_every: 3", "search_every: 3", "search_skip_below is 0"},
      {"search_skip_below: 100", "search_skip_below: 100", "search_every is 1"},
      {"search_every: 2 search_skip_below: 500", "search_skip_below: 500", "cost_above (500)"},
      {"search_every: 2 search_skip_below: 100 cold_start: true", "search_every: 2", "cold_start"},
      {"light_from: 3 light_to: 12", "light_to: 12", "search_every above 1"},
      {"search_every: 99 search_skip_below: 100 light_from: 5 light_to: 5", "light_to: 5",
       "light_from below light_to"},
  };
  for (const auto& c : cases) {
    const std::string text = Config(c.fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_light.textproto", text, &config).ok()) << c.fields;
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << c.fields;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, c.named)))
        << c.fields;
    EXPECT_THAT(std::string(s.message()), HasSubstr(c.says)) << c.fields;
  }
  LoadedConfig config;
  for (const char* fields :
       {"search_every: 2 search_skip_below: 100",
        "search_every: 99 search_skip_below: 100 light_from: 3 light_to: 12"}) {
    ASSERT_TRUE(Load("soccer_light.textproto", Config(fields), &config).ok()) << fields;
    EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
  }
}

TEST(PlannerConfigTest, APauseAfterALostRescueWithoutARescueIsRefusedAtTheField) {
  const std::string text = Config("rescue { cost_above: 0 pause_after_lost: 5 }");
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_pause.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "pause_after_lost: 5")));
  ASSERT_TRUE(
      Load("soccer_pause.textproto", Config("rescue { pause_after_lost: 5 }"), &config).ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, AFullRescueAfterADecayWithoutADecayIsRefusedAtTheField) {
  for (const char* fields : {"rescue { full_after_decay: true }",
                             "rescue { population_decay: 1 full_after_decay: true }"}) {
    const std::string text = Config(fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_full_after_decay.textproto", text, &config).ok());
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << fields;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, "full_after_decay")));
  }
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_full_after_decay.textproto",
                   Config("rescue { population_decay: 1.25 full_after_decay: true }"), &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, AModelBasedRescueBesideTheCrossEntropySettingsIsRefusedAtTheField) {
  for (const char* fields :
       {"rescue { samples: 32 bayes { } }", "rescue { iterations: 3 bayes { } }",
        "rescue { population_decay: 1.25 bayes { } }",
        "rescue { full_after_narrowed: true bayes { } }",
        "rescue { narrowed_samples: 16 bayes { } }", "rescue { narrowed_iterations: 2 bayes { } }",
        "rescue { bayes { evaluations: 8 initial: 8 } }"}) {
    const std::string text = Config(fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_bayes.textproto", text, &config).ok()) << fields;
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << fields;
    const bool budget = std::string(fields).find("evaluations") != std::string::npos;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text,
                                                  budget ? "evaluations" : "bayes")))
        << s;
  }
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_bayes.textproto",
                   Config("rescue { stop_below: 100 bayes { evaluations: 64 } }"), &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, ANarrowedRescueOfFewerThanFourSamplesIsRefusedAtTheField) {
  for (const char* fields : {"rescue { narrowed_samples: 1 }", "rescue { narrowed_samples: 3 }"}) {
    const std::string text = Config(fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_narrowed.textproto", text, &config).ok()) << fields;
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << fields;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, "narrowed_samples")));
  }
  for (const char* fields : {"rescue { narrowed_samples: 0 }",
                             "rescue { narrowed_samples: 4 narrowed_iterations: 1 }"}) {
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_narrowed.textproto", Config(fields), &config).ok()) << fields;
    EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << fields << ValidatePlannerConfig(config);
  }
}

TEST(PlannerConfigTest, ADecayConfinedToHalfFixedTroubleWithoutBothIsRefusedAtTheField) {
  for (const char* fields : {"rescue { half_fixed_above: 150 decay_half_fixed_only: true }",
                             "rescue { population_decay: 1.25 decay_half_fixed_only: true }"}) {
    const std::string text = Config(fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_decay_half_fixed.textproto", text, &config).ok());
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << fields;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, "decay_half_fixed_only")));
  }
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_decay_half_fixed.textproto",
                   Config("rescue { half_fixed_above: 150 population_decay: 1.25 "
                          "decay_half_fixed_only: true }"),
                   &config)
                  .ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, PruningInGroupsWithoutPruningIsRefusedAtTheField) {
  // The shipped config prunes; groups without pruning, or with robust draws (which do not
  // prune), would only wait.
  for (const char* fields : {"prune: false prune_chunk: 8", "prune_chunk: 8 robust { draws: 2 }"}) {
    const std::string text = Config(fields);
    LoadedConfig config;
    ASSERT_TRUE(Load("soccer_prune_chunk.textproto", text, &config).ok());
    const absl::Status s = ValidatePlannerConfig(config);
    EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument) << fields;
    EXPECT_THAT(std::string(s.message()),
                StartsWith(::juggle::testing::Loc(config.config_path, text, "prune_chunk: 8")));
  }
  LoadedConfig config;
  ASSERT_TRUE(Load("soccer_prune_chunk.textproto", Config("prune_chunk: 8"), &config).ok());
  EXPECT_TRUE(ValidatePlannerConfig(config).ok()) << ValidatePlannerConfig(config);
}

TEST(PlannerConfigTest, ATaskBlockOfAnotherFamilyIsRefusedNamingBothFamilies) {
  // Both families have a planning task (planner/tasks.cc); a toss run with the soccer task's
  // block is refused at the block.
  const std::string text =
      ConfigOver("configs/toss_throw_planner.textproto", "soccer_juggle { cost { kick: 20 } }");
  LoadedConfig config;
  ASSERT_TRUE(Load("toss_soccer_block.textproto", text, &config).ok());
  const absl::Status s = ValidatePlannerConfig(config);
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()),
              StartsWith(::juggle::testing::Loc(config.config_path, text, "soccer_juggle {")));
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("planner.soccer_juggle: a planning task for soccer_juggle, but this run's "
                        "envs are of the toss family"));
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(config);
  ASSERT_TRUE(spec.ok());
  EXPECT_FALSE(PlannerController::Create(*spec, config).ok());
  // The shipped toss planner config is valid.
  absl::StatusOr<LoadedConfig> toss = LoadRunConfig(RepoPath("configs/toss_throw_planner.textproto"));
  ASSERT_TRUE(toss.ok()) << toss.status();
  EXPECT_TRUE(ValidatePlannerConfig(*toss).ok()) << ValidatePlannerConfig(*toss);
}

TEST(PlannerConfigTest, KickAndCostAtTheirOldPlaceLoadIntoTheSoccerTasksBlock) {
  // Configs and checkpoints written before the task seam keep loading.
  LoadedConfig config;
  ASSERT_TRUE(Load("old_place.textproto", Config("cost { kick: 20 } kick { cycles: 2 }"), &config).ok());
  EXPECT_FALSE(config.run.planner().has_cost());
  EXPECT_FALSE(config.run.planner().has_kick());
  EXPECT_EQ(config.run.planner().soccer_juggle().cost().kick(), 20);
  EXPECT_EQ(config.run.planner().soccer_juggle().kick().cycles(), 2);
  // The shipped config's kick limits survive a base config that sets them at the new place.
  EXPECT_EQ(config.run.planner().soccer_juggle().kick().phase_limit_s(), 0.15);
  EXPECT_TRUE(ValidatePlannerConfig(config).ok());
  ASSERT_TRUE(ApplyPlannerSettings("samples: 8 cost { kick: 30 }", &config).ok());
  EXPECT_EQ(config.run.planner().soccer_juggle().cost().kick(), 30);
  EXPECT_FALSE(config.run.planner().has_cost());
  EXPECT_TRUE(ApplyPlannerSettings("soccer_juggle { cost { kick: 40 } }", &config).ok());
  EXPECT_EQ(config.run.planner().soccer_juggle().cost().kick(), 40);
}

TEST(PlannerConfigTest, KickOrCostInBothPlacesIsAnErrorNamingFileLineAndField) {
  const std::string text = Config("cost { kick: 20 } soccer_juggle { cost { kick: 30 } }");
  const std::string path = WriteTemp("both_places.textproto", text);
  const absl::Status s = LoadRunConfig(path).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(s.message()), StartsWith(::juggle::testing::Loc(path, text, "cost {")));
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("planner.cost: set both here and in planner.soccer_juggle.cost"));
  LoadedConfig config;
  ASSERT_TRUE(Load("fine.textproto", Config(""), &config).ok());
  const absl::Status set =
      ApplyPlannerSettings("kick { cycles: 2 } soccer_juggle { kick { cycles: 3 } }", &config);
  EXPECT_THAT(std::string(set.message()),
              StartsWith("--planner-set:1:1: kick: set both here and in soccer_juggle"));
}

// --planner-set with another task's block (the task blocks are a oneof) merges into the config's
// block: the football config's kick limits stay, the second touch is added.
TEST(PlannerConfigTest, PlannerSettingsForAnotherTasksBlockMergeIntoIt) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(RepoPath("configs/football_trap_kick.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  ASSERT_EQ(config->run.planner().football().kick().phase_limit_s(), 0.15);
  ASSERT_TRUE(
      ApplyPlannerSettings("samples: 8 football { second_touch { enabled: true } }", &*config).ok());
  EXPECT_TRUE(config->run.planner().football().second_touch().enabled());
  EXPECT_EQ(config->run.planner().football().kick().phase_limit_s(), 0.15);
  EXPECT_EQ(config->run.planner().samples(), 8);
  EXPECT_FALSE(config->run.planner().has_soccer_juggle());
}

TEST(PlannerConfigTest, ThePlannerControllerRefusesAConfigWithoutAPlannerBlock) {
  absl::StatusOr<LoadedConfig> config =
      LoadRunConfig(RepoPath("configs/right_foot_recipe.textproto"));
  ASSERT_TRUE(config.ok()) << config.status();
  ASSERT_FALSE(config->run.has_planner());
  absl::StatusOr<std::shared_ptr<const EnvSpec>> spec = CreateEnvSpec(*config);
  ASSERT_TRUE(spec.ok()) << spec.status();
  const absl::StatusOr<std::unique_ptr<PlannerController>> c = PlannerController::Create(*spec, *config);
  EXPECT_EQ(c.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(c.status().message()), HasSubstr("right_foot_recipe.textproto: has no planner block"));
  EXPECT_THAT(std::string(c.status().message()), HasSubstr("configs/right_foot_planner.textproto"));
}

}  // namespace
}  // namespace juggle::planner
