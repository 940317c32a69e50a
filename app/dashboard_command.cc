// `juggle dashboard`: a run directory (finished, or still training locally) rendered as the
// learner's dashboard page in one self-contained HTML file, to open in a browser or attach to a
// report (docs/dashboard.md).
#include <cstdio>

#include "app/commands.h"
#include "common/file_io.h"
#include "learner/dashboard_report.h"

namespace juggle {

CommandBody AddDashboardCommand(CLI::App* cmd) {
  struct Flags {
    std::string run_dir, out;
  };
  auto f = std::make_shared<Flags>();
  cmd->add_option("--run_dir", f->run_dir, "run directory (its metrics.jsonl and checkpoints/)")
      ->required();
  cmd->add_option("--out", f->out, "HTML file to write (default: <run_dir>/dashboard.html)");
  return [f] {
    absl::StatusOr<DashboardReport> report = RenderRunDashboard(f->run_dir);
    if (!report.ok()) return Fail(report.status());
    const std::string out = f->out.empty() ? f->run_dir + "/dashboard.html" : f->out;
    if (absl::Status s = WriteFile(out, report->html); !s.ok()) return Fail(s);
    for (const std::string& note : report->notes) std::printf("note: %s\n", note.c_str());
    std::printf("wrote %s (%d iterations, %d evaluations, %zu bytes)\n", out.c_str(),
                report->iterations, report->evaluations, report->html.size());
    return 0;
  };
}

}  // namespace juggle
