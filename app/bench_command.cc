// `juggle bench sim|planner|physics|moe|ingest|broadcast|local|dashboard`: the benchmarks of bench/ (docs/performance.md).
#include "app/commands.h"
#include "app/policy_source.h"
#include "bench/benchmarks.h"
#include "common/eigen_policy.h"

namespace juggle {

CommandBody AddBenchCommand(CLI::App* cmd) {
  cmd->require_subcommand(1);
  auto sim = std::make_shared<SimBenchOptions>();
  auto moe = std::make_shared<MoeBenchOptions>();
  auto ingest = std::make_shared<IngestBenchOptions>();
  auto broadcast = std::make_shared<BroadcastBenchOptions>();
  auto local = std::make_shared<LocalBenchOptions>();
  auto dashboard = std::make_shared<DashboardBenchOptions>();

  CLI::App* s = cmd->add_subcommand("sim", "env steps/s on 1 and 2 threads vs bare mj_step");
  s->add_option("--config", sim->config, "run config")->capture_default_str();
  s->add_option("--envs", sim->envs, "envs in the pool")->check(Between(1, 10000))->capture_default_str();
  s->add_option("--steps", sim->steps, "batch steps per measurement")->check(Between(1, 1e6))->capture_default_str();
  s->add_option("--repeats", sim->repeats, "alternating repeats (best is reported)")
      ->check(Between(1, 100))->capture_default_str();

  auto plan = std::make_shared<PlannerBenchOptions>();
  CLI::App* pl = cmd->add_subcommand("planner", "the planner's rollouts on 1 and 2 threads and "
                                                "snapshot restores vs bare mj_step");
  pl->add_option("--config", plan->config, "run config (its planner settings)")->capture_default_str();
  pl->add_option("--replans", plan->replans, "re-plans of the planner's own episode per measurement")
      ->check(Between(1, 10000))->capture_default_str();
  pl->add_option("--repeats", plan->repeats, "alternating repeats (best is reported)")
      ->check(Between(1, 100))->capture_default_str();
  pl->add_option("--planner-set", plan->planner_set,
                 "planner settings over the config's, text format (e.g. 'samples: 8 iterations: 2')");
  pl->add_option("--proposal", plan->proposal_path,
                 "a policy (checkpoint, run directory or .jglpolicy) as every plan's prior: the same "
                 "episode is also planned with it, and the two compared");

  auto physics = std::make_shared<PhysicsBenchOptions>();
  CLI::App* ph = cmd->add_subcommand("physics", "mj_step's stages and the model's solver options "
                                                "as variants: speed and the physics they change");
  ph->add_option("--config", physics->config, "run config (its model)")->capture_default_str();
  ph->add_option("--states", physics->states, "control steps of a zero-action env replayed")
      ->check(Between(1, 1000000))->capture_default_str();
  ph->add_option("--repeats", physics->repeats, "rounds over the states, each variant in turn on every chunk of 50 (times summed)")
      ->check(Between(1, 100))->capture_default_str();

  CLI::App* m = cmd->add_subcommand("moe", "layer-wise vs weight-blended MoE, PPO update and "
                                             "Eigen inference speed");
  m->add_option("--reps", moe->reps, "repetitions per measurement (best is reported)")
      ->check(Between(1, 100))->capture_default_str();
  m->add_option("--threads", moe->threads, "torch threads")->check(Between(1, 256))->capture_default_str();
  m->add_option("--ppo_samples", moe->ppo_samples, "samples in the PPO-throughput batch")
      ->check(Between(1, 1e7))->capture_default_str();
  m->add_option("--worker_batch", moe->worker_batch, "batch of the Eigen inference measurement")
      ->check(Between(1, 1e6))->capture_default_str();

  CLI::App* i = cmd->add_subcommand("ingest", "unrolls/s one learner ingests from synthetic "
                                              "workers over loopback");
  i->add_option("--config", ingest->config, "run config (sets the obs size)")->capture_default_str();
  i->add_option("--workers", ingest->workers, "synthetic worker streams")
      ->check(Between(1, 4096))->capture_default_str();
  i->add_option("--seconds", ingest->seconds, "measurement time")->check(Between(0.1, 3600))->capture_default_str();
  i->add_option("--unrolls_per_chunk", ingest->unrolls_per_chunk, "unrolls in each chunk")
      ->check(Between(1, 10000))->capture_default_str();

  CLI::App* b = cmd->add_subcommand("broadcast", "snapshot broadcast time to connected workers");
  b->add_option("--config", broadcast->config, "run config (sets the policy size)")->capture_default_str();
  b->add_option("--workers", broadcast->workers, "connected workers")
      ->check(Between(1, 4096))->capture_default_str();
  b->add_option("--rounds", broadcast->rounds, "broadcasts measured")->check(Between(1, 1000))->capture_default_str();

  CLI::App* l = cmd->add_subcommand("local", "local-mode iteration time vs sampling alone + "
                                             "update alone");
  l->add_option("--config", local->config, "run config")->capture_default_str();
  l->add_option("--iterations", local->iterations, "iterations of each measurement")
      ->check(Between(1, 100000))->capture_default_str();

  auto soak = std::make_shared<SoakBenchOptions>();
  CLI::App* k = cmd->add_subcommand("soak", "a learner process and synthetic workers under worker "
                                            "and learner kills: RSS and unroll accounts");
  k->add_option("--config", soak->config, "asynchronous run config")->capture_default_str();
  k->add_option("--workers", soak->workers, "synthetic workers")
      ->check(Between(1, 4096))->capture_default_str();
  k->add_option("--envs", soak->envs_per_worker, "unrolls per contribution")
      ->check(Between(2, 1024))->capture_default_str();
  k->add_option("--minutes", soak->minutes, "duration")->check(Between(0.2, 1440))->capture_default_str();
  k->add_option("--interval", soak->contribution_interval_s, "seconds between a worker's contributions")
      ->check(Between(0, 60))->capture_default_str();
  k->add_option("--kill_every", soak->kill_every_s, "seconds between worker kills")
      ->check(Between(1, 3600))->capture_default_str();
  k->add_option("--seed", soak->seed, "seed of the chaos schedule")->capture_default_str();
  k->add_option("--run_dir", soak->run_dir, "learner run directory and logs (default: a temporary one)");

  auto scale = std::make_shared<ScaleBenchOptions>();
  CLI::App* sc = cmd->add_subcommand("scale", "one learner and 8..64 worker processes on loopback: "
                                              "where the learner saturates");
  sc->add_option("--config", scale->config, "asynchronous run config")->capture_default_str();
  sc->add_option("--workers", scale->workers, "worker process counts, comma-separated")
      ->capture_default_str();
  sc->add_option("--warmup", scale->warmup_s, "seconds before measuring")
      ->check(Between(0, 3600))->capture_default_str();
  sc->add_option("--seconds", scale->seconds, "seconds measured per count")
      ->check(Between(1, 3600))->capture_default_str();

  CLI::App* d = cmd->add_subcommand("dashboard", "local training's samples/s with and without "
                                                 "a client polling the dashboard");
  d->add_option("--config", dashboard->config, "run config")->capture_default_str();
  d->add_option("--phase_seconds", dashboard->phase_seconds, "length of each phase")
      ->check(Between(1, 3600))->capture_default_str();
  d->add_option("--repeats", dashboard->repeats, "quiet/polled phase pairs")
      ->check(Between(1, 100))->capture_default_str();
  d->add_option("--poll_hz", dashboard->poll_hz, "page refreshes per second while polled")
      ->check(Between(0.01, 100))->capture_default_str();

  auto play = std::make_shared<PlayBenchOptions>();
  CLI::App* p = cmd->add_subcommand("play", "what streaming the live page costs the simulation: "
                                            "steps/s without and with a viewer");
  p->add_option("--config", play->config, "run config")->capture_default_str();
  p->add_option("--phase_seconds", play->phase_seconds, "length of each phase")
      ->check(Between(0.5, 3600))->capture_default_str();
  p->add_option("--repeats", play->repeats, "quiet/watched phase pairs")
      ->check(Between(1, 100))->capture_default_str();
  p->add_option("--frame_rate", play->frame_rate, "frames per wall second at most")
      ->check(Between(1, 1000))->capture_default_str();

  return [=] {
    absl::Status status;
    if (p->parsed()) status = RunPlayBench(*play);
    if (s->parsed()) status = RunSimBench(*sim);
    if (pl->parsed() && !plan->proposal_path.empty()) {
      absl::StatusOr<PolicySource> proposal = LoadPolicySource(plan->proposal_path, plan->config);
      if (!proposal.ok()) return Fail(proposal.status());
      plan->proposal = proposal->policy;
      plan->proposal_path = proposal->path;
    }
    if (pl->parsed()) status = RunPlannerBench(*plan);
    if (ph->parsed()) status = RunPhysicsBench(*physics);
    if (m->parsed()) status = RunMoeBench(*moe);
    if (i->parsed()) status = RunIngestBench(*ingest);
    if (k->parsed()) status = RunSoakBench(*soak);
    if (sc->parsed()) status = RunScaleBench(*scale);
    if (b->parsed()) status = RunBroadcastBench(*broadcast);
    if (l->parsed()) status = RunLocalBench(*local);
    if (d->parsed()) status = RunDashboardBench(*dashboard);
    return status.ok() ? 0 : Fail(status);
  };
}

}  // namespace juggle
