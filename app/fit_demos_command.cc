// `juggle fit-demos`: offline behaviour cloning of a run's saved demonstration buffer
// (learner/demo_fit.h, docs/learning.md "Planner-guided training"): how well a student network
// fits the planner's labels and how well it generalizes to the newest ones it was not shown.
#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "app/commands.h"
#include "common/config_loader.h"
#include "common/file_io.h"
#include "envs/registry.h"
#include "common/policy_file.h"
#include "envs/policy_config.h"
#include "learner/demo_fit.h"

namespace juggle {

CommandBody AddFitDemosCommand(CLI::App* cmd) {
  struct Flags {
    std::string demos;
    std::string config = "configs/right_foot_guided.textproto";
    std::string model_set;
    std::string actions = "14,15,16,17,20";
    std::string json;
    std::string save_policy;
    DemoFitOptions options;
  };
  auto f = std::make_shared<Flags>();
  cmd->add_option("--demos", f->demos, "a saved demonstration buffer, or the run directory "
                  "that holds one (RUN_DIR/demos.jgld); several, comma-separated, are joined "
                  "in that order (the last one's newest rows are held out)")
      ->required();
  cmd->add_option("--config", f->config,
                  "run config whose model is fitted and whose imitation.min_label_std weights "
                  "the error")
      ->capture_default_str();
  cmd->add_option("--model-set", f->model_set,
                  "model settings over the config's, text format (e.g. 'architecture: MLP "
                  "mlp_hidden: [512, 512]')");
  cmd->add_option("--epochs", f->options.epochs, "passes over the training rows")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  cmd->add_option("--minibatch", f->options.minibatch, "rows per Adam step")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--lr", f->options.lr, "Adam's learning rate")
      ->check(CLI::Range(1e-8, 1.0))
      ->capture_default_str();
  cmd->add_option("--held-out", f->options.held_out, "the newest share of rows, not trained on")
      ->check(CLI::Range(0.01, 0.9))
      ->capture_default_str();
  cmd->add_option("--train-rows", f->options.train_rows,
                  "train on only the newest this many of the training rows (0: all): a learning "
                  "curve against one held-out set")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  cmd->add_option("--rows", f->options.rows,
                  "only the oldest this many rows (0: all), to compare buffers at one size")
      ->check(CLI::Range(int64_t{0}, int64_t{1} << 40));
  cmd->add_option("--obs-prefix", f->options.obs_prefix,
                  "only the first this many observation floats (0: all): e.g. a buffer with "
                  "the previous action in its observations fitted without it")
      ->check(CLI::Range(0, 1000000));
  cmd->add_flag("--random-split", f->options.random_split,
               "hold out a random share instead of the newest (states alike in time on both "
               "sides: how well the network fits states like those it saw)");
  cmd->add_option("--previous-label", f->options.previous_label_unroll,
                  "diagnostic: extend each observation by the label of the state before it "
                  "(unrolls of this many steps, e.g. the run's ppo.unroll_length; 0: off)")
      ->check(CLI::Range(0, 100000));
  cmd->add_option("--seed", f->options.seed, "torch's generator")->capture_default_str();
  cmd->add_option("--threads", f->options.threads, "torch threads")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_option("--actions", f->actions,
                  "actions reported one by one (comma-separated; the default: the right leg's "
                  "hip, knee and ankle actions the planner moves)")
      ->capture_default_str();
  cmd->add_option("--json", f->json, "also write one JSON line per epoch here");
  cmd->add_option("--save-policy", f->save_policy,
                  "write the fitted actor as a self-contained policy file (.jglpolicy) under "
                  "--config, for juggle eval/render (the buffer's observations must be the "
                  "config's, whole: no --obs-prefix or --previous-label)");
  return [f] {
    absl::StatusOr<LoadedConfig> config = LoadRunConfig(f->config);
    if (!config.ok()) return Fail(config.status());
    config::ModelConfig model = config->run.model();
    if (!f->model_set.empty()) {
      config::ModelConfig changes;
      absl::StatusOr<SourceLocator> parsed = ParseTextMessage(f->model_set, "--model-set", &changes);
      if (!parsed.ok()) return Fail(parsed.status());
      model.MergeFrom(changes);
    }
    f->options.min_label_std = config->run.imitation().min_label_std();
    for (absl::string_view a : absl::StrSplit(f->actions, ',', absl::SkipEmpty())) {
      int index;
      if (!absl::SimpleAtoi(a, &index)) {
        return Fail(absl::InvalidArgumentError(absl::StrCat("--actions: '", a, "' is not an action index")));
      }
      f->options.actions.push_back(index);
    }
    // One buffer, or several joined in the order given (the last one's newest rows are the
    // newest of all, so held out first).
    std::vector<DemoBuffer> parts;
    std::string path;
    for (absl::string_view one : absl::StrSplit(f->demos, ',', absl::SkipEmpty())) {
      std::string p(one);
      if (p.size() < 5 || p.substr(p.size() - 5) != ".jgld") p += "/demos.jgld";
      absl::StatusOr<std::string> bytes = ReadFile(p);
      if (!bytes.ok()) return Fail(bytes.status());
      absl::StatusOr<DemoBuffer> part = DemoBuffer::Parse(*bytes);
      if (!part.ok()) {
        return Fail(absl::InvalidArgumentError(absl::StrCat(p, ": ", part.status().message())));
      }
      parts.push_back(*std::move(part));
      path += (path.empty() ? "" : ",") + p;
    }
    if (parts.empty()) return Fail(absl::InvalidArgumentError("--demos names no buffer"));
    absl::StatusOr<DemoBuffer> demos = parts[0];
    if (parts.size() > 1) {
      int64_t rows = 0;
      for (const DemoBuffer& part : parts) rows += part.size();
      demos = DemoBuffer(std::max<int64_t>(rows, 1), parts[0].obs_dim(), parts[0].act_dim());
      for (const DemoBuffer& part : parts) {
        if (absl::StatusOr<int64_t> added = demos->AddAll(part); !added.ok()) {
          return Fail(absl::InvalidArgumentError(
              absl::StrCat("--demos: ", added.status().message())));
        }
      }
    }
    std::printf("fit-demos: %lld labelled states (%d observations, %d actions) from %s; the "
                "newest %.0f%% held out; %d epochs of minibatch %d, lr %g\n",
                static_cast<long long>(f->options.rows > 0 ? std::min<int64_t>(f->options.rows, demos->size())
                                                           : demos->size()),
                demos->obs_dim(), demos->act_dim(),
                path.c_str(), 100 * f->options.held_out, f->options.epochs, f->options.minibatch,
                f->options.lr);
    std::string json;
    std::shared_ptr<const EnvSpec> spec;
    if (!f->save_policy.empty()) {
      absl::StatusOr<std::shared_ptr<const EnvSpec>> made = CreateEnvSpec(*config);
      if (!made.ok()) return Fail(made.status());
      spec = *made;
      if (spec->obs_dim() != demos->obs_dim() || spec->act_dim() != demos->act_dim() ||
          f->options.obs_prefix > 0 || f->options.previous_label_unroll > 0) {
        return Fail(absl::InvalidArgumentError(absl::StrCat(
            "--save-policy: ", f->config, " makes an env with ", spec->obs_dim(),
            " observations and ", spec->act_dim(), " actions; the fitted policy sees ",
            f->options.obs_prefix > 0 ? f->options.obs_prefix : demos->obs_dim(),
            f->options.previous_label_unroll > 0 ? " plus the previous label" : "",
            " and acts on ", demos->act_dim())));
      }
    }
    FlatParameters fitted;
    absl::StatusOr<std::vector<DemoFitEpoch>> fit =
        FitDemos(*demos, model, f->options, [&](const DemoFitEpoch& r) {
          std::string line = absl::StrFormat("epoch %d: train %.4f held-out %.4f |", r.epoch,
                                             r.train_error, r.held_out_error);
          std::string j = absl::StrFormat(
              "{\"epoch\":%d,\"train_error\":%.6g,\"held_out_error\":%.6g,\"seconds\":%.1f",
              r.epoch, r.train_error, r.held_out_error, r.seconds);
          for (size_t i = 0; i < r.action_rms.size(); ++i) {
            absl::StrAppendFormat(&line, " a%d rms %.4f R2 %.2f", f->options.actions[i],
                                  r.action_rms[i], r.action_r2[i]);
            absl::StrAppendFormat(&j, ",\"rms_%d\":%.6g,\"r2_%d\":%.4f", f->options.actions[i],
                                  r.action_rms[i], f->options.actions[i], r.action_r2[i]);
          }
          absl::StrAppendFormat(&line, " (%.0f s)", r.seconds);
          absl::StrAppend(&json, j, "}\n");
          std::printf("%s\n", line.c_str());
          std::fflush(stdout);
        }, f->save_policy.empty() ? nullptr : &fitted);
    if (!fit.ok()) return Fail(fit.status());
    if (!f->save_policy.empty()) {
      config::ExportedPolicy exported;
      *exported.mutable_model() = model;
      exported.set_obs_dim(demos->obs_dim());
      exported.set_act_dim(demos->act_dim());
      exported.set_parameters(fitted.Serialize());
      exported.set_source(absl::StrCat("fit-demos ", path));
      if (absl::Status s = WritePolicyFile(f->save_policy,
                                           WithStoredConfig(exported, *config, *spec));
          !s.ok()) {
        return Fail(s);
      }
      std::printf("wrote the fitted policy to %s\n", f->save_policy.c_str());
    }
    if (!f->json.empty()) {
      if (absl::Status s = WriteFile(f->json, json); !s.ok()) return Fail(s);
    }
    return 0;
  };
}

}  // namespace juggle
