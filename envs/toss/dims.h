// Sizes of the toss-juggling tasks' interface (Chemin & Lee §4.1; docs/toss.md), shared by workers and the learner.
// Everything is in the right arm's frame; the left arm is mirrored into it (envs/toss/world.h).
#ifndef JUGGLE_ENVS_TOSS_DIMS_H_
#define JUGGLE_ENVS_TOSS_DIMS_H_

namespace juggle::toss {

// Controlled joints 𝒥 = {neck, shoulder, elbow, wrist}: the action is their target angles.
constexpr int kTossJoints = 4;
// S_catch = {p_hand (2), ṗ_hand (2), p_ball (2), ṗ_ball (2), 𝒥 (4)}.
constexpr int kTossCatchObs = 12;
// S_throw = S_catch ∪ {t_throw (1), v̄_throw (2)}.
constexpr int kTossThrowObs = kTossCatchObs + 3;
// Balls in the toss model (configs/models/toss_arms.xml): patterns juggle at most this many.
constexpr int kTossModelBalls = 7;

}  // namespace juggle::toss

#endif  // JUGGLE_ENVS_TOSS_DIMS_H_
