#include "envs/football/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "absl/strings/str_format.h"

namespace juggle::football {

namespace {

double Norm(const double v[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

// The angle between a and b (radians), from atan2(|a × b|, a·b): accurate at small angles.
double Angle(const double a[3], const double b[3]) {
  const double cross[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                           a[0] * b[1] - a[1] * b[0]};
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::atan2(Norm(cross), dot);
}

double Ratio(double numerator, int denominator) {
  return denominator > 0 ? numerator / denominator : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

KickScore ScoreKick(const KickAttempt& kick, double window_s) {
  KickScore score;
  if (!kick.touched) return score;
  double angles = 0, speeds = 0;
  for (const BallVelocitySample& s : kick.after_touch) {
    if (s.t < 0 || s.t > window_s) continue;
    angles += Angle(s.velocity, kick.target_direction);
    speeds += std::abs(Norm(s.velocity) - kick.target_speed);
    ++score.samples;
  }
  if (score.samples == 0) return score;
  score.success = true;
  score.direction_deviation_deg = angles / score.samples * 180 / M_PI;
  score.speed_deviation_mps = speeds / score.samples;
  return score;
}

KickErrors SignedKickErrors(const KickAttempt& kick, double window_s) {
  KickErrors e;
  if (!kick.touched) return e;
  const double* t = kick.target_direction;
  const double target_azimuth = std::atan2(t[1], t[0]);
  const double target_elevation = std::atan2(t[2], std::hypot(t[0], t[1]));
  int samples = 0;
  for (const BallVelocitySample& s : kick.after_touch) {
    if (s.t < 0 || s.t > window_s) continue;
    const double* v = s.velocity;
    e.azimuth_deg += std::remainder(std::atan2(v[1], v[0]) - target_azimuth, 2 * M_PI);
    e.elevation_deg += std::atan2(v[2], std::hypot(v[0], v[1])) - target_elevation;
    e.speed_mps += Norm(v) - kick.target_speed;
    ++samples;
  }
  if (samples == 0) return KickErrors{};
  e.valid = true;
  e.azimuth_deg *= 180 / M_PI / samples;
  e.elevation_deg *= 180 / M_PI / samples;
  e.speed_mps /= samples;
  return e;
}

KickFloor KickDeviationFloor(const KickAttempt& kick, double window_s) {
  KickFloor floor;
  if (!kick.touched) return floor;
  std::vector<const double*> v;
  for (const BallVelocitySample& s : kick.after_touch) {
    if (s.t >= 0 && s.t <= window_s) v.push_back(s.velocity);
  }
  if (v.empty()) return floor;
  auto elevation = [](const double* u) { return std::atan2(u[2], std::hypot(u[0], u[1])); };
  std::vector<const double*> by_elevation = v;
  std::sort(by_elevation.begin(), by_elevation.end(),
            [&](const double* a, const double* b) { return elevation(a) < elevation(b); });
  const double* median = by_elevation[(by_elevation.size() - 1) / 2];
  std::vector<double> speeds;
  for (const double* u : v) speeds.push_back(Norm(u));
  std::vector<double> sorted = speeds;
  std::sort(sorted.begin(), sorted.end());
  const double median_speed = sorted[(sorted.size() - 1) / 2];
  for (size_t i = 0; i < v.size(); ++i) {
    floor.direction_deg += Angle(v[i], median);
    floor.speed_mps += std::abs(speeds[i] - median_speed);
  }
  floor.direction_deg *= 180 / M_PI / v.size();
  floor.speed_mps /= v.size();
  return floor;
}

TrapScore ScoreTrap(const TrapAttempt& trap, int frames) {
  TrapScore score;
  score.success = trap.designated_first_before_ground && trap.within_reach_after;
  score.handball = score.success && trap.arms_touched;
  if (frames > 0 && static_cast<int>(trap.relative_speed_after_touch.size()) >= frames) {
    double sum = 0;
    for (int i = 0; i < frames; ++i) sum += trap.relative_speed_after_touch[i];
    score.relative_speed = sum / frames;
    score.measured_speed = true;
  }
  return score;
}

void FootballMetrics::Add(const TrapScore& trap) {
  ++traps_;
  if (!trap.success) return;
  ++trap_successes_;
  if (trap.handball) ++handballs_;
  if (trap.measured_speed) {
    ++speed_measured_;
    relative_speed_sum_ += trap.relative_speed;
  }
}

void FootballMetrics::Add(const KickScore& kick) {
  ++kicks_;
  if (!kick.success) return;
  ++kick_successes_;
  direction_sum_ += kick.direction_deviation_deg;
  speed_sum_ += kick.speed_deviation_mps;
}

void FootballMetrics::AddTrapThenKick(bool success) {
  ++sequences_;
  if (success) ++sequence_successes_;
}

double FootballMetrics::tsr() const { return Ratio(trap_successes_, traps_); }
double FootballMetrics::hrts() const { return Ratio(handballs_, trap_successes_); }
double FootballMetrics::rbspt_mps() const { return Ratio(relative_speed_sum_, speed_measured_); }
double FootballMetrics::ksr() const { return Ratio(kick_successes_, kicks_); }
double FootballMetrics::kdd_deg() const { return Ratio(direction_sum_, kick_successes_); }
double FootballMetrics::ksd_mps() const { return Ratio(speed_sum_, kick_successes_); }
double FootballMetrics::trap_kick() const { return Ratio(sequence_successes_, sequences_); }

std::string FootballMetrics::SummaryLine() const {
  return absl::StrFormat(
      "tsr=%.3f hrts=%.3f rbspt_mps=%.3f ksr=%.3f kdd_deg=%.3f ksd_mps=%.3f trap_kick=%.3f",
      tsr(), hrts(), rbspt_mps(), ksr(), kdd_deg(), ksd_mps(), trap_kick());
}

}  // namespace juggle::football
