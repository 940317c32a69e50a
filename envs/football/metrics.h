// PhysicsFC's trap and kick metrics (seed 002; docs/football.md, "Metrics"), as issue 45 defines
// success: per attempt from what an env records, and their aggregate as `juggle eval`'s last
// line. Pure functions and a plain accumulator; no MuJoCo.
//   trap: success when the designated body part touches the ball first, before the ball touches
//     the ground, and the ball is within reach afterwards (TSR); among successes, those the
//     hands or arms touched (HRTS); the ball's speed relative to the root over the 5 control
//     frames right after the touch (RBSPT, m/s);
//   kick: success when the kick touched the ball (KSR); over the first 1/6 s after the touch,
//     the mean angle between the ball's velocity and the target direction (KDD, degrees) and
//     the mean |ball speed − target speed| (KSD, m/s), over successful kicks.
#ifndef JUGGLE_ENVS_FOOTBALL_METRICS_H_
#define JUGGLE_ENVS_FOOTBALL_METRICS_H_

#include <string>
#include <vector>

namespace juggle::football {

// The ball's velocity `t` seconds after the kick's touch (t ≥ 0).
struct BallVelocitySample {
  double t = 0;
  double velocity[3] = {0, 0, 0};
};

struct KickAttempt {
  bool touched = false;
  double target_direction[3] = {1, 0, 0};  // need not be unit length
  double target_speed = 0;                 // m/s
  std::vector<BallVelocitySample> after_touch;
};

struct KickScore {
  bool success = false;
  double direction_deviation_deg = 0;  // KDD of this kick (0 unless success)
  double speed_deviation_mps = 0;      // KSD of this kick
  int samples = 0;                     // samples inside the window
};

// Scores one kick over [0, window_s] after the touch. A touched kick with no sample in the
// window scores as a failure (nothing was measured).
KickScore ScoreKick(const KickAttempt& kick, double window_s = 1.0 / 6.0);

// A kick's signed errors over the same window, the smooth counterparts of KDD and KSD (the
// planner's refinement steps on them, planner/football/kick_task.cc): the mean azimuth and
// elevation of the ball's velocity less the target's (degrees; azimuth about +z, wrapped to
// ±180, positive to the left) and the mean speed less the target speed (m/s). `valid` is false
// without a touch or a sample in the window.
struct KickErrors {
  bool valid = false;
  double azimuth_deg = 0;
  double elevation_deg = 0;
  double speed_mps = 0;
};
KickErrors SignedKickErrors(const KickAttempt& kick, double window_s = 1.0 / 6.0);

// The least KDD and KSD any target could have given this ball's flight over the window (gravity
// turns and slows the ball inside it, so even a perfect aim keeps some of both): the mean angle
// of the samples' velocities to the median sample's by elevation, and the mean |speed − the
// median speed|. The samples' directions lie on one great circle (a velocity under gravity
// alone stays in the plane of its start and the vertical), where the median minimizes the sum
// of angular distances. 0 and 0 without a touch or a sample in the window.
struct KickFloor {
  double direction_deg = 0;
  double speed_mps = 0;
};
KickFloor KickDeviationFloor(const KickAttempt& kick, double window_s = 1.0 / 6.0);

struct TrapAttempt {
  bool designated_first_before_ground = false;
  bool within_reach_after = false;
  bool arms_touched = false;  // hands or arms, at any time of the trap
  // |ball velocity − root velocity| (m/s) per control frame from the first touch on.
  std::vector<double> relative_speed_after_touch;
};

struct TrapScore {
  bool success = false;
  bool handball = false;       // a success the arms touched
  double relative_speed = 0;   // RBSPT of this trap: mean over the first `frames` frames
  bool measured_speed = false; // false when fewer frames were recorded
};

TrapScore ScoreTrap(const TrapAttempt& trap, int frames = 5);

// The evaluation's aggregate over attempts.
class FootballMetrics {
 public:
  void Add(const TrapScore& trap);
  void Add(const KickScore& kick);
  // One trap-then-kick sequence of the state machine: whether it succeeded (the designated
  // part's trap brought the ball into the kick's zone, the kick succeeded, no fall).
  void AddTrapThenKick(bool success);

  double tsr() const;        // successful traps / traps
  double hrts() const;       // handballs / successful traps
  double rbspt_mps() const;  // mean relative speed over successful traps with a measurement
  double ksr() const;        // successful kicks / kicks
  double kdd_deg() const;    // mean over successful kicks
  double ksd_mps() const;
  double trap_kick() const;  // successful sequences / sequences
  int traps() const { return traps_; }
  int kicks() const { return kicks_; }

  // "tsr=0.783 hrts=0.056 rbspt_mps=3.690 ksr=0.999 kdd_deg=4.790 ksd_mps=4.510 trap_kick=0.850"
  // (rates as fractions; nan where no attempt of that kind was made).
  std::string SummaryLine() const;

 private:
  int traps_ = 0, trap_successes_ = 0, handballs_ = 0, speed_measured_ = 0;
  double relative_speed_sum_ = 0;
  int kicks_ = 0, kick_successes_ = 0;
  double direction_sum_ = 0, speed_sum_ = 0;
  int sequences_ = 0, sequence_successes_ = 0;
};

}  // namespace juggle::football

#endif  // JUGGLE_ENVS_FOOTBALL_METRICS_H_
