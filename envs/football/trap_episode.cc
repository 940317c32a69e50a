#include "envs/football/trap_episode.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "envs/football/spec.h"

namespace juggle::football {
namespace {

constexpr double kDeg = M_PI / 180;
constexpr const char* kPartGeoms[kTrapParts] = {"", "right_foot", "right_shin", "chest", "head"};
constexpr const char* kArmBodies[] = {"right_shoulder", "right_elbow", "right_wrist",
                                      "left_shoulder",  "left_elbow",  "left_wrist"};
// Apex retries before the steepest, fastest launch is used (validated to reach).
constexpr int kApexTries = 32;

absl::Status Invalid(const SourceLocator& where, const FieldPath& path, const std::string& what) {
  return absl::InvalidArgumentError(absl::StrCat(where.Where(path), ": ", what));
}

}  // namespace

double LobMeetingHeight(const TrapBodies& bodies, config::TrapPart part) {
  return bodies.standing_centre[part][2] + (part == config::FOOT ? kFootLobLift : 0);
}

std::vector<config::TrapPart> LobParts(const config::TrapPasses& passes) {
  std::vector<config::TrapPart> parts;
  for (int p : passes.parts()) parts.push_back(static_cast<config::TrapPart>(p));
  if (parts.empty()) parts = {config::FOOT, config::LOWER_LEG, config::TORSO, config::HEAD};
  return parts;
}

absl::StatusOr<TrapBodies> ResolveTrapBodies(const mjModel* model, const double* standing_qpos,
                                            const config::TrapPasses& passes,
                                            const SourceLocator& where) {
  TrapBodies b;
  b.geom.fill(-1);
  b.body.fill(-1);
  MjDataPtr d(mj_makeData(model));
  mju_copy(d->qpos, standing_qpos, humanoid::kCharacterNq);
  mj_kinematics(model, d.get());
  for (int p = 1; p < kTrapParts; ++p) {
    const int g = mj_name2id(model, mjOBJ_GEOM, kPartGeoms[p]);
    if (g < 0) continue;
    b.geom[p] = g;
    b.body[p] = model->geom_bodyid[g];
    b.bounds[p] = MeasureGeomBounds(model, g);
    GeomBoundsCentre(b.bounds[p], model, d.get(), b.standing_centre[p].data());
  }
  for (int i = 0; i < passes.parts_size(); ++i) {
    const int p = passes.parts(i);
    if (p <= 0 || p >= kTrapParts) {
      return Invalid(where, {{"trap"}, {"parts", i}}, "choose FOOT, LOWER_LEG, TORSO or HEAD");
    }
    if (b.geom[p] < 0) {
      return Invalid(where, {{"trap"}, {"parts", i}},
                     absl::StrCat("the model has no geom '", kPartGeoms[p], "' for ",
                                  config::TrapPart_Name(static_cast<config::TrapPart>(p))));
    }
  }
  if (b.geom[config::FOOT] < 0) {
    return Invalid(where, {{"model_file"}}, "the model has no geom 'right_foot' (ground passes)");
  }
  for (config::TrapPart p : LobParts(passes)) {
    if (b.geom[p] < 0) {
      return Invalid(where, {{"trap"}, {"parts"}},
                     absl::StrCat("the model has no geom '", kPartGeoms[p],
                                  "': list the parts it has"));
    }
  }
  b.is_arm.assign(model->nbody, 0);
  for (const char* name : kArmBodies) {
    const int body = mj_name2id(model, mjOBJ_BODY, name);
    if (body >= 0) b.is_arm[body] = 1;
  }
  return b;
}

absl::Status ValidateTrapPasses(const config::TrapPasses& t, const SourceLocator& where,
                                double highest_part_m, double ball_radius, double g) {
  auto order = [&](const char* min, double lo, const char* max, double hi) -> absl::Status {
    if (lo > hi) return Invalid(where, {{"trap"}, {min}}, absl::StrCat("must be <= trap.", max));
    return absl::OkStatus();
  };
  for (const absl::Status& s :
       {order("launch_angle_min_deg", t.launch_angle_min_deg(), "launch_angle_max_deg",
              t.launch_angle_max_deg()),
        order("launch_speed_min_mps", t.launch_speed_min_mps(), "launch_speed_max_mps",
              t.launch_speed_max_mps()),
        order("meet_ahead_min_m", t.meet_ahead_min_m(), "meet_ahead_max_m", t.meet_ahead_max_m()),
        order("ground_arrival_speed_min_mps", t.ground_arrival_speed_min_mps(),
              "ground_arrival_speed_max_mps", t.ground_arrival_speed_max_mps())}) {
    if (!s.ok()) return s;
  }
  if (t.lob_fraction() > 0) {
    const double vz = t.launch_speed_max_mps() * std::sin(t.launch_angle_max_deg() * kDeg);
    const double apex = t.launch_height_m() + vz * vz / (2 * g);
    const double highest = std::max(highest_part_m + t.meet_raise_m(), ball_radius) + 0.05;
    if (apex < highest) {
      return Invalid(where, {{"trap"}, {"launch_speed_max_mps"}},
                     absl::StrCat("the fastest, steepest lob peaks at ", apex,
                                  " m: it cannot come down through the highest drawn part's "
                                  "meeting point at ",
                                  highest, " m; raise the launch speed or angle"));
    }
  }
  return absl::OkStatus();
}

TrapEpisode DrawTrapEpisode(const FootballSpec& spec, Rng& rng) {
  const config::TrapPasses& t = spec.football().trap();
  const TrapBodies& bodies = spec.trap_bodies();
  const double r = spec.ball().radius;
  const double g = -spec.model()->opt.gravity[2];
  TrapEpisode e;
  const bool lob = rng.Uniform() < t.lob_fraction();
  const std::vector<config::TrapPart> parts = LobParts(t);
  const int drawn = std::min<int>(parts.size() - 1, static_cast<int>(rng.Uniform() * parts.size()));
  e.part = lob ? parts[drawn] : config::FOOT;
  const double incoming = rng.Uniform(-t.incoming_bearing_max_deg(), t.incoming_bearing_max_deg());
  const double ahead = rng.Uniform(t.meet_ahead_min_m(), t.meet_ahead_max_m());
  const double side = rng.Uniform(-t.meet_side_m(), t.meet_side_m());
  const double raise = rng.Uniform(0, t.meet_raise_m());
  const double arrival = rng.Uniform(t.ground_arrival_speed_min_mps(),
                                     t.ground_arrival_speed_max_mps());
  // Spin: a uniformly random axis (z and azimuth), a uniform magnitude.
  const double axis_z = rng.Uniform(-1, 1), axis_phi = rng.Uniform(0, 2 * M_PI);
  const double spin_draw = rng.Uniform(0, t.spin_max_radps());  // drawn for every pass
  const double spin = lob ? spin_draw : 0;
  // The pass travels along −x turned by the incoming bearing; u points back toward its source.
  const double travel = M_PI + incoming * kDeg;
  const double u[2] = {-std::cos(travel), -std::sin(travel)};
  const double across[2] = {-u[1], u[0]};
  const std::array<double, 3>& centre = bodies.standing_centre[e.part];
  const double out = bodies.bounds[e.part].thinnest() + r + ahead;
  e.meet_point[0] = centre[0] + out * u[0] + side * across[0];
  e.meet_point[1] = centre[1] + out * u[1] + side * across[1];
  e.meet_point[2] = std::max(LobMeetingHeight(bodies, e.part) + raise, r);
  if (lob) {
    absl::StatusOr<Pass> pass;
    for (int tries = 0; tries < kApexTries; ++tries) {
      const double angle = rng.Uniform(t.launch_angle_min_deg(), t.launch_angle_max_deg());
      const double speed = rng.Uniform(t.launch_speed_min_mps(), t.launch_speed_max_mps());
      pass = LobPassThrough(e.meet_point, travel, speed, angle, t.launch_height_m(), r, g);
      if (pass.ok()) break;
    }
    if (!pass.ok()) {
      pass = LobPassThrough(e.meet_point, travel, t.launch_speed_max_mps(),
                            t.launch_angle_max_deg(), t.launch_height_m(), r, g);
    }
    e.pass = *pass;  // ValidateTrapPasses: the steepest, fastest lob reaches every point
    const double s = std::sqrt(std::max(0.0, 1 - axis_z * axis_z));
    e.spin[0] = spin * s * std::cos(axis_phi);
    e.spin[1] = spin * s * std::sin(axis_phi);
    e.spin[2] = spin * axis_z;
  } else {
    e.meet_point[2] = r;
    e.pass = GroundPassArrivingAt(e.meet_point, travel, arrival, t.ground_start_distance_m(),
                                  RollingDeceleration(spec.model(), spec.ball()), r);
  }
  const double skip = std::max(0.0, e.pass.meet_s - t.lead_s());
  e.pass = AdvancePass(e.pass, skip, g, RollingDeceleration(spec.model(), spec.ball()));
  return e;
}

void PlaceTrapBall(const FootballSpec& spec, const TrapEpisode& e, mjData* d) {
  const PitchBall& b = spec.ball();
  double* ball = d->qpos + b.qpos;
  mju_copy3(ball, e.pass.start);
  ball[3] = 1;
  ball[4] = ball[5] = ball[6] = 0;
  double* v = d->qvel + b.dof;
  mju_copy3(v, e.pass.velocity);
  if (e.pass.kind == PassKind::kGround) {
    // Rolling without slipping: ω = ẑ × v / r.
    v[3] = -v[1] / b.radius;
    v[4] = v[0] / b.radius;
    v[5] = 0;
  } else {
    mju_copy3(v + 3, e.spin);
    // MuJoCo's Euler step updates the velocity before the position, so a free flight falls
    // ½·g·dt·t below the analytic one; starting ½·g·dt faster upward cancels it exactly.
    v[2] -= 0.5 * spec.model()->opt.gravity[2] * spec.model()->opt.timestep;
  }
}

void NoteTrapContacts(const FootballSpec& spec, const mjData* d, TrapEpisode* e) {
  if (e->settled) return;  // the trap is over (TRAP_KICK goes on to the kick)
  const mjModel* m = spec.model();
  const PitchBall& ball = spec.ball();
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    if (c.geom1 != ball.geom && c.geom2 != ball.geom) continue;
    const int other = c.geom1 == ball.geom ? c.geom2 : c.geom1;
    if (other == ball.pitch_geom) {
      if (e->first_body < 0) e->turf_before_touch = true;
      continue;
    }
    const int body = m->geom_bodyid[other];
    if (body == 0) continue;  // the goal frame
    if (spec.trap_bodies().is_arm[body]) e->arms_touched = true;
    if (e->first_body < 0) {
      e->first_body = body;
      e->first_touch_s = d->time;
    }
  }
}

void AfterTrapControlStep(const FootballSpec& spec, const mjData* d, TrapEpisode* e) {
  if (e->first_body < 0 || e->settled) return;
  const double* ball_v = d->qvel + spec.ball().dof;
  std::vector<double>& speeds = e->attempt.relative_speed_after_touch;
  if (static_cast<int>(speeds.size()) < kRelativeSpeedFrames) {
    const double diff[3] = {ball_v[0] - d->qvel[0], ball_v[1] - d->qvel[1], ball_v[2] - d->qvel[2]};
    speeds.push_back(mju_norm3(diff));
  }
  if (d->time - e->first_touch_s < spec.football().trap().settle_s() - 1e-9) return;
  EndTrap(spec, d, e);
}

void EndTrap(const FootballSpec& spec, const mjData* d, TrapEpisode* e) {
  const double* ball = d->qpos + spec.ball().qpos;
  e->end_distance_m = std::hypot(ball[0] - d->qpos[0], ball[1] - d->qpos[1]);
  e->settled = true;
  e->attempt.designated_first_before_ground =
      e->first_body == spec.trap_bodies().body[e->part] &&
      (e->pass.kind == PassKind::kGround || !e->turf_before_touch);
  e->attempt.within_reach_after = e->end_distance_m <= spec.football().trap().reach_m();
  e->attempt.arms_touched = e->arms_touched;
}

}  // namespace juggle::football
