// `juggle dashboard`: a run directory (finished, or still training locally) rendered as the
// learner's dashboard page in one self-contained HTML file, to open in a browser or attach to a
// report; or an evaluation's JSON lines (`juggle eval --json`, any controller) with its config,
// the control graph coloured by the evaluation's success per node (docs/dashboard.md).
#include <cstdio>

#include "app/commands.h"
#include "envs/registry.h"
#include "common/file_io.h"
#include "learner/dashboard_report.h"

namespace juggle {

CommandBody AddDashboardCommand(CLI::App* cmd) {
  struct Flags {
    std::string run_dir, eval, config, out;
  };
  auto f = std::make_shared<Flags>();
  auto* run_dir =
      cmd->add_option("--run_dir", f->run_dir, "run directory (its metrics.jsonl and checkpoints/)");
  auto* eval = cmd->add_option("--eval", f->eval,
                               "an evaluation's JSON lines (juggle eval --json=FILE) instead of a run");
  cmd->add_option("--config", f->config, "with --eval: the config the evaluation ran");
  cmd->add_option("--out", f->out,
                  "HTML file to write (default: <run_dir>/dashboard.html, or FILE.html for --eval)");
  run_dir->excludes(eval);
  return [f] {
    if (f->run_dir.empty() == f->eval.empty()) {
      std::fprintf(stderr, "error: give --run_dir, or --eval with --config\n");
      return 2;
    }
    absl::StatusOr<DashboardReport> report;
    std::string out = f->out;
    if (!f->eval.empty()) {
      if (f->config.empty()) {
        std::fprintf(stderr, "error: --eval needs the --config the evaluation ran\n");
        return 2;
      }
      absl::StatusOr<LoadedConfig> config = LoadRunConfig(f->config);
      if (!config.ok()) return Fail(config.status());
      report = RenderEvalDashboard(f->eval, *config);
      if (out.empty()) out = f->eval + ".html";
    } else {
      report = RenderRunDashboard(f->run_dir);
      if (out.empty()) out = f->run_dir + "/dashboard.html";
    }
    if (!report.ok()) return Fail(report.status());
    if (absl::Status s = WriteFile(out, report->html); !s.ok()) return Fail(s);
    for (const std::string& note : report->notes) std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s (%d iterations, %d evaluations, %zu bytes)\n", out.c_str(),
                report->iterations, report->evaluations, report->html.size());
    return 0;
  };
}

}  // namespace juggle
