#include "envs/football/passes.h"

#include <cmath>

#include "absl/strings/str_cat.h"
#include "envs/ballistic.h"

namespace juggle::football {

namespace {

constexpr double kDeg = M_PI / 180;

absl::Status Range(const char* min_name, double min, const char* max_name, double max,
                   double lowest, double highest) {
  if (!(min >= lowest && max <= highest && min <= max)) {
    return absl::InvalidArgumentError(absl::StrCat(min_name, " ", min, " and ", max_name, " ", max,
                                                   " must satisfy ", lowest, " <= ", min_name,
                                                   " <= ", max_name, " <= ", highest));
  }
  return absl::OkStatus();
}

// A pass of `kind` arriving at `target` (x, y; at height target_z) along the horizontal
// heading, started `distance` m back along it at height start_z with horizontal speed `speed`.
Pass Toward(PassKind kind, const double target[2], double heading_rad, double distance,
            double speed, double start_z, double target_z) {
  const double cx = std::cos(heading_rad), cy = std::sin(heading_rad);
  Pass p;
  p.kind = kind;
  p.start[0] = target[0] - distance * cx;
  p.start[1] = target[1] - distance * cy;
  p.start[2] = start_z;
  p.velocity[0] = speed * cx;
  p.velocity[1] = speed * cy;
  p.target[0] = target[0];
  p.target[1] = target[1];
  p.target[2] = target_z;
  return p;
}

}  // namespace

absl::Status ValidatePassRanges(const PassRanges& r) {
  if (!(r.lob_fraction >= 0 && r.lob_fraction <= 1)) {
    return absl::InvalidArgumentError(absl::StrCat("lob_fraction ", r.lob_fraction,
                                                   " must lie in [0, 1]"));
  }
  for (const absl::Status& s :
       {Range("landing_distance_min", r.landing_distance_min, "landing_distance_max",
              r.landing_distance_max, 0, 20),
        Range("launch_angle_min_deg", r.launch_angle_min_deg, "launch_angle_max_deg",
              r.launch_angle_max_deg, 1, 89),
        Range("launch_speed_min", r.launch_speed_min, "launch_speed_max", r.launch_speed_max,
              0.5, 40),
        Range("ground_arrival_speed_min", r.ground_arrival_speed_min,
              "ground_arrival_speed_max", r.ground_arrival_speed_max, 0, 40)}) {
    if (!s.ok()) return s;
  }
  if (!(r.landing_bearing_max_deg >= 0 && r.landing_bearing_max_deg <= 180 &&
        r.incoming_bearing_max_deg >= 0 && r.incoming_bearing_max_deg <= 180)) {
    return absl::InvalidArgumentError("the bearings must lie in [0, 180] degrees");
  }
  if (!(r.launch_height > 0 && r.launch_height < 3)) {
    return absl::InvalidArgumentError(absl::StrCat("launch_height ", r.launch_height,
                                                   " m must lie in (0, 3)"));
  }
  if (!(r.ground_start_distance > 0 && r.ground_start_distance <= 60 &&
        r.ground_aim_distance >= 0 && r.ground_aim_distance <= 20)) {
    return absl::InvalidArgumentError(
        "ground_start_distance must lie in (0, 60] m and ground_aim_distance in [0, 20] m");
  }
  return absl::OkStatus();
}

Pass LobPassLandingAt(const double landing[2], double heading_rad, double speed,
                      double angle_deg, double launch_height, double ball_radius, double g) {
  const double vz = speed * std::sin(angle_deg * kDeg);
  const double horizontal = speed * std::cos(angle_deg * kDeg);
  // Up from the launch height and down to the landing height (the ball resting on the turf).
  const double flight = SecondsToFall(vz, launch_height - ball_radius, g);
  Pass p = Toward(PassKind::kLob, landing, heading_rad, horizontal * flight, horizontal,
                  launch_height, ball_radius);
  p.velocity[2] = vz;
  p.arrival_s = flight;
  p.arrival_speed = std::hypot(horizontal, vz - g * flight);
  p.meet_s = flight;
  return p;
}

absl::StatusOr<Pass> LobPassThrough(const double point[3], double heading_rad, double speed,
                                    double angle_deg, double launch_height, double ball_radius,
                                    double g) {
  const double vz = speed * std::sin(angle_deg * kDeg);
  const double horizontal = speed * std::cos(angle_deg * kDeg);
  const double apex = launch_height + vz * vz / (2 * g);
  if (apex < point[2] + 0.05) {
    return absl::FailedPreconditionError(absl::StrCat(
        "a lob at ", speed, " m/s and ", angle_deg, " deg peaks at ", apex,
        " m, below the meeting point's ", point[2], " m (+0.05)"));
  }
  // Coming down: the vertical speed at the landing (centre at ball_radius), then at the point.
  const double landing_vz = std::sqrt(vz * vz + 2 * g * (launch_height - ball_radius));
  const double point_vz = std::sqrt(landing_vz * landing_vz - 2 * g * (point[2] - ball_radius));
  const double before_landing = (landing_vz - point_vz) / g;
  const double landing[2] = {point[0] + horizontal * before_landing * std::cos(heading_rad),
                             point[1] + horizontal * before_landing * std::sin(heading_rad)};
  Pass p = LobPassLandingAt(landing, heading_rad, speed, angle_deg, launch_height, ball_radius, g);
  p.meet_s = p.arrival_s - before_landing;
  return p;
}

Pass AdvancePass(const Pass& pass, double t, double g, double deceleration) {
  Pass p = pass;
  if (pass.kind == PassKind::kLob) {
    for (int c = 0; c < 3; ++c) p.start[c] = pass.start[c] + pass.velocity[c] * t;
    p.start[2] -= 0.5 * g * t * t;
    p.velocity[2] = pass.velocity[2] - g * t;
  } else {
    const double v0 = std::hypot(pass.velocity[0], pass.velocity[1]);
    if (v0 > 0) {
      const double travelled = v0 * t - 0.5 * deceleration * t * t;
      const double v = v0 - deceleration * t;
      for (int c = 0; c < 2; ++c) {
        p.start[c] = pass.start[c] + pass.velocity[c] / v0 * travelled;
        p.velocity[c] = pass.velocity[c] / v0 * v;
      }
    }
  }
  p.arrival_s = pass.arrival_s - t;
  p.meet_s = pass.meet_s - t;
  return p;
}

Pass GroundPassArrivingAt(const double aim[2], double heading_rad, double arrival_speed,
                          double distance, double deceleration, double ball_radius) {
  // v0² = v² + 2·a·d; the roll lasts (v0 − v) / a.
  const double v0 = std::sqrt(arrival_speed * arrival_speed + 2 * deceleration * distance);
  Pass p = Toward(PassKind::kGround, aim, heading_rad, distance, v0, ball_radius, ball_radius);
  p.arrival_s = deceleration > 0 ? (v0 - arrival_speed) / deceleration : distance / v0;
  p.arrival_speed = arrival_speed;
  p.meet_s = p.arrival_s;
  return p;
}

Pass SamplePass(const PassRanges& r, double ball_radius, double g, double deceleration,
                Rng& rng) {
  // Every draw is made whatever the kind, so a pass's index fixes its stream position.
  const double kind = rng.Uniform();
  const double incoming = rng.Uniform(-r.incoming_bearing_max_deg, r.incoming_bearing_max_deg);
  const double landing_distance = rng.Uniform(r.landing_distance_min, r.landing_distance_max);
  const double landing_bearing =
      rng.Uniform(-r.landing_bearing_max_deg, r.landing_bearing_max_deg) * kDeg;
  const double angle = rng.Uniform(r.launch_angle_min_deg, r.launch_angle_max_deg);
  const double speed = rng.Uniform(r.launch_speed_min, r.launch_speed_max);
  const double arrival = rng.Uniform(r.ground_arrival_speed_min, r.ground_arrival_speed_max);
  // The pass comes toward the character from in front: it travels along −x (heading π),
  // turned by the incoming bearing.
  const double travel = M_PI + incoming * kDeg;
  if (kind < r.lob_fraction) {
    const double landing[2] = {landing_distance * std::cos(landing_bearing),
                               landing_distance * std::sin(landing_bearing)};
    return LobPassLandingAt(landing, travel, speed, angle, r.launch_height, ball_radius, g);
  }
  const double aim[2] = {r.ground_aim_distance, 0};
  return GroundPassArrivingAt(aim, travel, arrival, r.ground_start_distance, deceleration,
                              ball_radius);
}

}  // namespace juggle::football
