#include "planner/soccer_juggle/kick_memory.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_split.h"
#include "common/file_io.h"
#include "planner/soccer_juggle/cost.h"

namespace juggle::planner {

std::optional<KickContext> KickContextOf(const soccer_juggle::JuggleEnv& env) {
  const soccer_juggle::JuggleEnvState& s = env.state();
  if (!s.kick_touched || s.touched_this_step) return std::nullopt;
  const KickOutcome k = PredictKickOutcome(env);
  if (!k.valid) return std::nullopt;
  const double* v = env.data()->qvel;
  return KickContext{k.timing, k.dx, k.dy, k.apex, v[0], v[1]};
}

std::string FormatKickMemoryRow(const KickContext& context, const KickDecision& decision) {
  std::string row;
  for (double x : context) absl::StrAppendFormat(&row, "%.6g ", x);
  for (int i = 0; i < kKickVariables; ++i) {
    absl::StrAppendFormat(&row, i + 1 < kKickVariables ? "%.6g " : "%.6g\n", decision[i]);
  }
  return row;
}

KickMemory::KickMemory(std::vector<std::pair<KickContext, KickDecision>> rows,
                       const config::PlannerCost& cost)
    : scales_{cost.timing_scale_s(), cost.landing_scale(),   cost.landing_scale(),
              cost.apex_scale(),     cost.com_speed_scale(), cost.com_speed_scale()},
      rows_(std::move(rows)) {}

absl::StatusOr<KickMemory> KickMemory::Load(const std::string& path,
                                            const config::PlannerCost& cost) {
  absl::StatusOr<std::string> text = ReadFile(path);
  if (!text.ok()) {
    return absl::NotFoundError(absl::StrCat("kick memory ", path, ": ", text.status().message()));
  }
  std::vector<std::pair<KickContext, KickDecision>> rows;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(*text, '\n')) {
    ++line_number;
    const size_t hash = line.find('#');
    if (hash != absl::string_view::npos) line = line.substr(0, hash);
    std::vector<absl::string_view> fields = absl::StrSplit(line, ' ', absl::SkipWhitespace());
    if (fields.empty()) continue;
    const int want = kKickContextSize + kKickVariables;
    if (static_cast<int>(fields.size()) != want) {
      return absl::InvalidArgumentError(absl::StrFormat(
          "%s:%d: %d numbers, expected %d (6 context values and 5 kick variables)", path,
          line_number, fields.size(), want));
    }
    std::pair<KickContext, KickDecision> row;
    for (int i = 0; i < want; ++i) {
      double x = 0;
      if (!absl::SimpleAtod(fields[i], &x) || !std::isfinite(x)) {
        return absl::InvalidArgumentError(absl::StrFormat(
            "%s:%d: field %d '%s' is not a finite number", path, line_number, i + 1, fields[i]));
      }
      (i < kKickContextSize ? row.first[i] : row.second[i - kKickContextSize]) = x;
    }
    rows.push_back(row);
  }
  if (rows.empty()) {
    return absl::InvalidArgumentError(absl::StrCat(path, ": no kicks in the memory"));
  }
  return KickMemory(std::move(rows), cost);
}

std::vector<KickDecision> KickMemory::Nearest(const KickContext& context, int k) const {
  std::vector<double> distance(rows_.size());
  for (size_t r = 0; r < rows_.size(); ++r) {
    double sum = 0;
    for (int i = 0; i < kKickContextSize; ++i) {
      sum += std::pow((rows_[r].first[i] - context[i]) / scales_[i], 2);
    }
    distance[r] = sum;
  }
  std::vector<int> order(rows_.size());
  std::iota(order.begin(), order.end(), 0);
  const int n = std::min<int>(k, order.size());
  std::partial_sort(order.begin(), order.begin() + n, order.end(), [&](int a, int b) {
    return distance[a] < distance[b] || (distance[a] == distance[b] && a < b);
  });
  std::vector<KickDecision> out;
  for (int i = 0; i < n; ++i) out.push_back(rows_[order[i]].second);
  return out;
}

}  // namespace juggle::planner
