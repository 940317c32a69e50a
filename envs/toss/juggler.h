// TossJuggler: pattern juggling with two arms (Chemin & Lee §3, Fig. 4; docs/toss.md). Each hand runs a mode
// machine — empty: catch mode, holding: throw mode — and the beat clock sequences the throws of
// a siteswap: beat k (right hand on even k) comes at (k + 1)·P_hand/2 — beat −1 at t = 0 —
// and throws s[k mod period] with the ball that hand holds.
//   value ≥ 2  released with the palm's velocity (auto-release); the target is Eq. 1–3's;
//   value 1    handed over to the other hand (Eq. 1 gives it no flight time; not in the paper);
//   value 0    nothing.
// The catch policy sees the next ball due at its hand; the throw policy sees the held ball,
// the time left to its beat and its target velocity; the left arm runs both through the mirror.
// The balls start as if the pattern had always run: each ball thrown on a beat ≤ −1 flies on its
// scheduled parabola (beat −1's just released), or is in its hand if its catch time (its beat
// − D_ratio·P_hand) has passed. Pattern 3: one ball in the right hand for beat 0, two in the
// air.
// A run ends at the first drop (ball below drop_z), at a beat whose ball is not in hand
// (missed beat), on divergence, or after max_throws throws.
#ifndef JUGGLE_ENVS_TOSS_JUGGLER_H_
#define JUGGLE_ENVS_TOSS_JUGGLER_H_

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "common/eigen_policy.h"
#include "common/rng.h"
#include "envs/toss/base_controller.h"
#include "envs/toss/juggle_schedule.h"
#include "envs/toss/siteswap.h"
#include "envs/toss/world.h"
#include "record/trajectory.h"

namespace juggle::toss {

struct TossPolicies {
  // Trained policies; null means the zero action (the arm holds its home pose).
  const EigenPolicy* catcher = nullptr;
  const EigenPolicy* thrower = nullptr;
};

struct JugglerOptions {
  int max_throws = 200;
  uint64_t seed = 1;
  // Start perturbation: arm angles ± start_noise (rad, speeds ± 10×); balls in flight at the
  // start ± ball_noise (m) in position and ± ball_speed_noise (m/s) in velocity.
  double start_noise = 0.05;
  double ball_noise = 0.02;
  double ball_speed_noise = 0.1;
  // Test oracle and scripted baseline: a release sets the ball's velocity to the schedule's
  // target instead of the palm's (the position stays the palm's).
  bool ideal_release = false;
};

enum class JuggleEnd { kMaxThrows, kDropped, kMissedBeat, kDiverged };
const char* JuggleEndName(JuggleEnd end);

struct JuggleRunResult {
  int throws = 0;    // throws made (released, handed over) before the run ended
  int catches = 0;
  int good_throws = 0;  // releases that pass IsGoodThrow
  JuggleEnd end = JuggleEnd::kMaxThrows;
  double seconds = 0;
  // Over the released throws: mean |v − v̄| (m/s) and |p − p̄| (m) at the release, the largest
  // |v − v̄|, and per throw value the sum and count of |v − v̄| (v̄: the schedule's, still air).
  int releases = 0;
  double mean_velocity_error = 0;
  double mean_position_error = 0;
  double max_velocity_error = 0;
  std::map<int, std::pair<double, int>> velocity_error_by_value;
  // Over the catches: mean |hand_z − z_ball| at the catch (m).
  double mean_catch_height_error = 0;
  // Arm states (right arm's frame) where a policy took over: the catching hand at each catch
  // (the throw policy starts there) and the throwing hand at each release (the catch policy
  // starts there). `juggle toss --record-states` writes them as training start states.
  std::vector<TossArmState> throw_starts, catch_starts;
};

// What happened to one hand in the last Step.
struct HandEvents {
  bool caught = false;
  double catch_height_error = 0;  // |hand_z − z_ball| at the catch (m)
  double catch_palm_speed = 0;    // |ṗ_hand| at the catch (m/s)
  bool released = false;          // a throw left the hand (handoffs are not releases)
  int value = 0;                  // the released throw's siteswap value
  Vec2 release_position, release_velocity, target_velocity;
  bool good_throw = false;        // IsGoodThrow
};

class TossJuggler {
 public:
  // INVALID_ARGUMENT for patterns with more balls than the model has (7) or throws above 35.
  static absl::StatusOr<std::unique_ptr<TossJuggler>> Create(std::shared_ptr<const TossSpec> spec,
                                                            const Siteswap& pattern,
                                                            TossPolicies policies,
                                                            JugglerOptions options);
  // A transition run (envs/toss/juggle_schedule.h): balls brought into play appear in the
  // throwing hand a dwell time before their beat; balls taken out are put away on their beat.
  static absl::StatusOr<std::unique_ptr<TossJuggler>> Create(std::shared_ptr<const TossSpec> spec,
                                                            const JuggleSchedule& schedule,
                                                            TossPolicies policies,
                                                            JugglerOptions options);
  // A recording of runs (`juggle toss --record`, record/trajectory.h): its outcome labels (the
  // shared ones, then max_throws, dropped, missed_beat) and channels: beat, throws, each hand's
  // mode (catch/throw), palm positions, and each ball's x, z and mode (parked/free/held).
  static TrajectoryBuilder NewRecording(const TossSpec& spec, int balls,
                                        const std::string& config_path);

  // Runs to the end; the start and every control step are appended to `recording` (episode
  // 0) if given.
  JuggleRunResult Run(TrajectoryBuilder* recording = nullptr);

  // One control step; false once the run is over (then Step must not be called again).
  // `right_action` (right arm's frame), if given, drives the right arm instead of its policy:
  // in-loop training (envs/toss/loop_env.h).
  bool Step(const float* right_action = nullptr, TrajectoryBuilder* recording = nullptr);
  bool over() const { return over_; }
  // The run so far (final once over()).
  const JuggleRunResult& result() const { return result_; }
  // The hand whose ball (a drop: the hand it was due at) or beat (a missed beat) ended the run.
  Hand end_hand() const { return end_hand_; }
  const HandEvents& events(Hand hand) const { return events_[static_cast<int>(hand)]; }
  // Mode machine: `hand` holds a ball it will release at its beat (throw mode with a throw of
  // positive flight time due; handoffs and empty beats excluded).
  bool HoldsThrow(Hand hand) const;
  // The free ball due next at `hand`, or −1 (none, or the other hand passes `hand` a ball
  // first: then `hand` waits at home).
  int IncomingBall(Hand hand) const;
  // The observation `hand`'s policy sees now: S_throw (kTossThrowObs floats) if it holds a
  // ball, else S_catch about IncomingBall (kTossCatchObs).
  void WriteObservation(Hand hand, float* obs) const;
  const TossWorld& world() const { return world_; }
  TossWorld* mutable_world() { return &world_; }
  const JuggleSchedule& schedule() const { return schedule_; }
  // Passes into `next` from the first beat not yet prepared for (balls brought in ahead
  // included): JuggleSchedule::SwitchAt. Returns that beat. INVALID_ARGUMENT (nothing changed)
  // for more balls than the model has, or SwitchAt's errors; FAILED_PRECONDITION once over.
  absl::StatusOr<int> SwitchPattern(const Siteswap& next);
  // An exact copy: it steps bit for bit as this runtime would (snapshots of the loop env).
  std::unique_ptr<TossJuggler> Clone() const;

 private:
  struct Ball {
    int next_beat = 0;  // beat on which it is thrown next
    bool out = false;   // taken out of play (parked); may be brought in again
  };
  TossJuggler(std::shared_ptr<const TossSpec> spec, const JuggleSchedule& schedule,
              TossPolicies policies, JugglerOptions options);
  TossJuggler(const TossJuggler&) = default;  // Clone
  // Brings the balls of add-beats into their hands once their dwell has begun; false when a
  // hand is not empty for it (a missed beat).
  bool BringInBalls();
  int DwellSteps() const;
  void PlaceInitialBalls(Rng* rng);
  int Value(int beat) const;
  int BeatStep(int beat) const;
  Hand DestinationHand(int ball) const;
  // Beat `beat` passes its ball to the other hand (a 1, or a throw Eq. 1 gives no flight time).
  bool IsHandoff(int beat) const;
  void Act(Hand hand);
  // The base controller's targets for `hand` in its current mode (REQUIRES: base_).
  JointTargets BaseTargets(Hand hand) const;
  void Finish(JuggleEnd end, Hand hand);
  bool DoBeat(int beat);  // false: missed beat
  void Capture(TrajectoryBuilder* recording) const;

  std::shared_ptr<const TossSpec> spec_;
  JuggleSchedule schedule_;
  int next_add_beat_ = 0;  // the next beat BringInBalls looks at
  TossPolicies policies_;
  JugglerOptions options_;
  TossWorld world_;
  // With TossConfig.base: the base controllers, and the wind they correct for.
  std::optional<TossBaseController> base_;
  WindEstimator wind_;
  std::vector<Ball> balls_;
  int step_ = 0;
  int next_beat_ = 0;
  JuggleRunResult result_;
  double velocity_error_sum_ = 0, position_error_sum_ = 0, catch_height_error_sum_ = 0;
  int releases_ = 0;
  bool over_ = false;
  Hand end_hand_ = Hand::kRight;
  std::array<HandEvents, 2> events_{};
};

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_JUGGLER_H_
