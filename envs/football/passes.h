// Passes to a standing character, generated as PhysicsFC (seed 002) trains its trap: lob passes
// by projectile initialization — the landing point, the launch angle and speed are sampled and
// the start is computed back from them, so every lob lands where it was asked — and ground
// passes that roll in on the turf. Pure functions of the parameters and one Rng; no MuJoCo.
// The models have no air drag (envs/ballistic.h); the roll decelerates at a constant rate
// (configs/models/football_pitch.xml, docs/football.md "The pitch").
#ifndef JUGGLE_ENVS_FOOTBALL_PASSES_H_
#define JUGGLE_ENVS_FOOTBALL_PASSES_H_

#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "common/rng.h"

namespace juggle::football {

// Where passes come from and arrive, in the character's frame at the start (x forward, y left,
// z up; the origin under its root). Ranges are [min, max]; angles in degrees.
struct PassRanges {
  double lob_fraction = 0.8;  // the rest are ground passes
  // Lob passes: the ball centre's landing point (at ball-radius height) within an annulus in
  // front of the character, the horizontal direction it comes from, the launch.
  double landing_distance_min = 0.3, landing_distance_max = 0.9;  // m from the origin
  double landing_bearing_max_deg = 30;  // |angle of the landing point off +x|
  double incoming_bearing_max_deg = 30;  // |angle, off −x, of the direction it comes from|
  double launch_angle_min_deg = 30, launch_angle_max_deg = 60;
  double launch_speed_min = 8, launch_speed_max = 14;  // m/s
  double launch_height = 0.13;  // m, the ball centre at the launch (just off the turf)
  // Ground passes: arrive at the aim point in front of the character at this speed, from
  // this far away, along the same incoming bearings.
  double ground_aim_distance = 0.4;  // m ahead of the origin
  double ground_arrival_speed_min = 2, ground_arrival_speed_max = 6;  // m/s
  double ground_start_distance = 12;  // m from the aim point
};

// INVALID_ARGUMENT naming the first field out of order or out of physical range.
absl::Status ValidatePassRanges(const PassRanges& ranges);

enum class PassKind { kLob, kGround };

struct Pass {
  PassKind kind = PassKind::kLob;
  double start[3] = {0, 0, 0};     // ball centre at t = 0
  double velocity[3] = {0, 0, 0};  // ball centre velocity at t = 0 (a ground pass rolls)
  double target[3] = {0, 0, 0};    // lob: the landing point; ground: the aim point
  double arrival_s = 0;            // when it lands (lob) or reaches the aim point (ground)
  double arrival_speed = 0;        // m/s at that moment
  // When the ball's centre passes the pass's meeting point (LobPassThrough; else arrival_s).
  double meet_s = 0;
};

// A lob launched at `speed` m/s, `angle_deg` above the horizontal, from `launch_height`, that
// lands with its centre at `landing` (x, y, ball_radius) travelling along the horizontal
// direction `heading_rad` (atan2 of its velocity): the start computed back along the flight.
// Gravity g > 0 m/s².
Pass LobPassLandingAt(const double landing[2], double heading_rad, double speed,
                      double angle_deg, double launch_height, double ball_radius, double g);

// A ball rolling along `heading_rad` that reaches `aim` (x, y) at `arrival_speed` m/s after
// rolling `distance` m on turf that slows it at `deceleration` m/s² (rolling without slipping:
// ω = v / r about the horizontal axis across its heading, written in Pass.velocity as linear
// velocity only; envs set the spin).
Pass GroundPassArrivingAt(const double aim[2], double heading_rad, double arrival_speed,
                          double distance, double deceleration, double ball_radius);

// A lob launched as LobPassLandingAt's whose centre comes down through `point` (x, y, z; z at
// least the ball radius) on its way to the landing beyond it. FAILED_PRECONDITION when the
// flight's apex does not reach point[2] (with 0.05 m to spare).
absl::StatusOr<Pass> LobPassThrough(const double point[3], double heading_rad, double speed,
                                    double angle_deg, double launch_height, double ball_radius,
                                    double g);

// The pass `t` seconds after its start (0 <= t <= arrival_s): start and velocity moved along
// the flight (a lob: free fall; a ground pass: the roll slowing at `deceleration`), the times
// shortened by t.
Pass AdvancePass(const Pass& pass, double t, double g, double deceleration);

// One pass drawn from `ranges` (REQUIRES: ValidatePassRanges ok).
Pass SamplePass(const PassRanges& ranges, double ball_radius, double g, double deceleration,
                Rng& rng);

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_PASSES_H_
