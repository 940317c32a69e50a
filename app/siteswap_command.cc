// `juggle siteswap`: analyse a vanilla siteswap (validity, balls, state, the physical throw
// schedule of Chemin & Lee's Eq. 1-3, docs/siteswap.md), find the shortest transition between two patterns, or
// enumerate patterns. The last line of every report is key=value pairs for scripts.
// Exit status: 0 ok, 1 invalid pattern (or patterns without a transition), 2 usage error.
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/escaping.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "app/command.h"
#include "app/commands.h"
#include "envs/toss/siteswap.h"

namespace juggle::toss {
namespace {

constexpr int kExitInvalid = 1;

struct SiteswapFlags {
  std::vector<std::string> patterns;
  double hand_period = 0.5, dwell_ratio = 0.7, hand_separation = 0.4;
  bool transition = false, enumerate = false;
  std::optional<int> balls, max_throw, period, max_period;
};

int UsageError(const std::string& message) {
  std::fprintf(stderr, "error: %s (see juggle siteswap --help)\n", message.c_str());
  return kExitUsage;
}

// The command-line text of a pattern, safe to print (bad bytes escaped).
std::string Printable(const std::string& text) { return absl::CHexEscape(text); }

int Analyse(const std::string& text, const ThrowPhysicsParams& params) {
  absl::StatusOr<std::vector<int>> throws = ParseSiteswapThrows(text);
  if (!throws.ok()) {
    std::printf("%s\nvalid=0 error=parse\n", std::string(throws.status().message()).c_str());
    return kExitInvalid;
  }
  const SiteswapCheck check = CheckSiteswap(*throws);
  if (!check.valid) {
    std::printf("siteswap %s: invalid: %s\nvalid=0 pattern=%s period=%d\n",
                FormatSiteswap(*throws).c_str(), check.reason.c_str(),
                FormatSiteswap(*throws).c_str(), check.period);
    return kExitInvalid;
  }
  absl::StatusOr<Siteswap> parsed = Siteswap::FromThrows(*throws);
  if (!parsed.ok()) {  // not expected after the check above
    std::printf("siteswap %s: invalid: %s\nvalid=0\n", FormatSiteswap(*throws).c_str(),
                std::string(parsed.status().message()).c_str());
    return kExitInvalid;
  }
  const Siteswap& s = *parsed;
  const int width = s.state_width();
  const std::string ground = FormatJugglingState(GroundState(s.balls()), width);
  std::printf("siteswap %s: valid, %d balls, period %d, max throw %d\n", s.ToString().c_str(),
              s.balls(), s.period(), s.max_throw());
  if (s.StartsInGroundState()) {
    std::printf("state %s: the ground state\n", s.StateString().c_str());
  } else if (s.IsGroundStatePattern()) {
    std::printf("state %s: not the ground state %s, but the rotation %s starts in it "
                "(a ground-state pattern)\n",
                s.StateString().c_str(), ground.c_str(),
                s.Rotated(s.GroundRotation()).ToString().c_str());
  } else {
    std::printf("state %s: excited (no rotation passes through the ground state %s)\n",
                s.StateString().c_str(), ground.c_str());
    absl::StatusOr<SiteswapTransition> in = FindTransition(GroundState(s.balls()), s.state(), width);
    absl::StatusOr<SiteswapTransition> out =
        FindTransition(s.state(), GroundState(s.balls()), width);
    if (in.ok() && out.ok()) {
      std::printf("from the ground state throw %s to enter it; throw %s to leave it\n",
                  FormatSiteswap(in->throws).c_str(), FormatSiteswap(out->throws).c_str());
    }
  }

  absl::StatusOr<std::vector<ThrowTiming>> schedule = ComputeSchedule(s, params);
  if (!schedule.ok()) return UsageError(std::string(schedule.status().message()));
  const double beat_s = params.hand_period_s / 2;
  std::printf(
      "schedule (Eq. 1-3): hand period %.3f s (beat %.3f s), dwell ratio %.2f (dwell %.3f s), "
      "hand separation %.3f m, g %.2f m/s^2; right hand on even beats, v_x > 0 towards the "
      "left hand\n",
      params.hand_period_s, beat_s, params.dwell_ratio, params.dwell_ratio * params.hand_period_s,
      params.hand_separation_m, params.gravity);
  std::printf("%4s %4s %5s %5s %-7s %8s %9s %8s %8s %8s %7s\n", "beat", "pos", "throw", "hand",
              "kind", "throw_s", "flight_s", "catch_s", "v_z_m/s", "v_x_m/s", "apex_m");
  for (const ThrowTiming& t : *schedule) {
    const std::string hands = absl::StrCat(HandName(t.hand), t.kind == ThrowKind::kEmpty ? "" : ">",
                                           t.kind == ThrowKind::kEmpty ? "" : HandName(t.catch_hand));
    std::printf("%4d %4d %5c %5s %-7s %8.3f %9.3f %8.3f %8.3f %8.3f %7.3f\n", t.beat, t.position,
                SiteswapThrowChar(t.value), hands.c_str(), ThrowKindName(t.kind), t.throw_time_s,
                t.flight_time_s, t.catch_time_s, t.v_z, t.v_x, t.apex_height_m);
  }
  std::printf("valid=1 pattern=%s balls=%d period=%d max_throw=%d state=%s ground=%d\n",
              s.ToString().c_str(), s.balls(), s.period(), s.max_throw(), s.StateString().c_str(),
              s.IsGroundStatePattern() ? 1 : 0);
  return 0;
}

int Transition(const std::string& from_text, const std::string& to_text) {
  const std::string keys =
      absl::StrCat("from=", Printable(from_text), " to=", Printable(to_text));
  absl::StatusOr<Siteswap> from = Siteswap::Parse(from_text);
  absl::StatusOr<Siteswap> to = Siteswap::Parse(to_text);
  for (const absl::StatusOr<Siteswap>* s : {&from, &to}) {
    if (!s->ok()) {
      std::printf("no transition: %s\nvalid=0 %s\n", std::string(s->status().message()).c_str(),
                  keys.c_str());
      return kExitInvalid;
    }
  }
  absl::StatusOr<SiteswapTransition> t = FindTransition(*from, *to);
  if (!t.ok()) {
    std::printf("no transition: %s\nvalid=0 %s\n", std::string(t.status().message()).c_str(),
                keys.c_str());
    return kExitInvalid;
  }
  const std::string throws = FormatSiteswap(t->throws);
  std::printf("transition from %s (state %s) to %s (state %s), %d balls: ",
              from->ToString().c_str(), FormatJugglingState(from->state(), t->width).c_str(),
              to->ToString().c_str(), FormatJugglingState(to->state(), t->width).c_str(),
              t->balls);
  if (t->throws.empty()) {
    std::printf("none needed (both start in the same state)\n");
  } else {
    std::printf("%s (%zu throw%s)\n", throws.c_str(), t->throws.size(),
                t->throws.size() == 1 ? "" : "s");
    for (size_t i = 0; i < t->throws.size(); ++i) {
      std::printf("  %s  throw %c  -> %s\n", FormatJugglingState(t->path[i], t->width).c_str(),
                  SiteswapThrowChar(t->throws[i]),
                  FormatJugglingState(t->path[i + 1], t->width).c_str());
    }
  }
  std::printf("  juggle: ...%s%s %s %s%s...\n", from->ToString().c_str(), from->ToString().c_str(),
              throws.empty() ? "|" : throws.c_str(), to->ToString().c_str(),
              to->ToString().c_str());
  std::printf("valid=1 balls=%d from=%s to=%s length=%zu transition=%s\n", t->balls,
              from->ToString().c_str(), to->ToString().c_str(), t->throws.size(), throws.c_str());
  return 0;
}

int Enumerate(const SiteswapFlags& f) {
  if (!f.balls || !f.max_throw) return UsageError("--enumerate needs --balls and --max_throw");
  if (f.period.has_value() == f.max_period.has_value()) {
    return UsageError("--enumerate needs exactly one of --period and --max_period");
  }
  const bool up_to = f.max_period.has_value();
  const int64_t balls = *f.balls, max_throw = *f.max_throw;
  const int64_t period = up_to ? *f.max_period : *f.period;
  std::vector<Siteswap> all;
  for (int p = up_to ? 1 : static_cast<int>(period); p <= period; ++p) {
    EnumerateOptions o;
    o.balls = static_cast<int>(balls);
    o.max_throw = static_cast<int>(max_throw);
    o.period = p;
    absl::StatusOr<std::vector<Siteswap>> found = EnumerateSiteswaps(o);
    if (!found.ok()) {
      if (found.status().code() == absl::StatusCode::kInvalidArgument) {
        return UsageError(std::string(found.status().message()));
      }
      std::fprintf(stderr, "juggle siteswap: %s\n", std::string(found.status().message()).c_str());
      return kExitInvalid;
    }
    all.insert(all.end(), found->begin(), found->end());
  }
  std::printf("%lld-ball siteswaps with throws up to %lld, period %s%lld (each once, in its "
              "rotation with the highest throw first): %zu\n",
              static_cast<long long>(balls), static_cast<long long>(max_throw),
              up_to ? "1 to " : "", static_cast<long long>(period), all.size());
  for (const Siteswap& s : all) {
    std::printf("  %-*s  period %2d  %-7s  state %s\n", static_cast<int>(period), s.ToString().c_str(),
                s.period(), s.IsGroundStatePattern() ? "ground" : "excited",
                s.StateString().c_str());
  }
  std::printf("count=%zu balls=%lld max_throw=%lld %s=%lld\n", all.size(),
              static_cast<long long>(balls), static_cast<long long>(max_throw),
              up_to ? "max_period" : "period", static_cast<long long>(period));
  return 0;
}

int RunSiteswapCommand(const SiteswapFlags& f) {
  const std::vector<std::string>& args = f.patterns;
  if (f.transition && f.enumerate) return UsageError("--transition and --enumerate exclude each other");
  if (f.enumerate) {
    if (!args.empty()) return UsageError("--enumerate takes no pattern");
    return Enumerate(f);
  }
  if (f.balls || f.max_throw || f.period || f.max_period) {
    return UsageError("--balls, --max_throw, --period and --max_period only apply to --enumerate");
  }
  if (f.transition) {
    if (args.size() != 2) return UsageError("--transition needs two patterns: FROM TO");
    return Transition(args[0], args[1]);
  }
  if (args.size() != 1) return UsageError("expected one pattern, e.g. juggle siteswap 531");
  ThrowPhysicsParams params;
  params.hand_period_s = f.hand_period;
  params.dwell_ratio = f.dwell_ratio;
  params.hand_separation_m = f.hand_separation;
  if (absl::Status s = params.Validate(); !s.ok()) return UsageError(std::string(s.message()));
  return Analyse(args[0], params);
}

}  // namespace
}  // namespace juggle::toss

namespace juggle {

CommandBody AddSiteswapCommand(CLI::App* cmd) {
  using toss::SiteswapFlags;
  auto f = std::make_shared<SiteswapFlags>();
  cmd->footer(
      "  juggle siteswap PATTERN [--hand_period=0.5 --dwell_ratio=0.7 --hand_separation=0.4]\n"
      "  juggle siteswap --transition FROM TO\n"
      "  juggle siteswap --enumerate --balls=3 --max_throw=5 (--period=3 | --max_period=3)\n"
      "Vanilla (asynchronous, solo) siteswaps: throws 0-9, a-z for 10-35. docs/siteswap.md.\n"
      "Exit status: 0 ok, 1 invalid pattern, 2 usage error.");
  cmd->add_option("patterns", f->patterns, "PATTERN, or FROM TO with --transition");
  cmd->add_option("--hand_period", f->hand_period,
                  "P_hand, s between two throws of one hand (paper Table 1)")
      ->capture_default_str();
  cmd->add_option("--dwell_ratio", f->dwell_ratio,
                  "D_ratio, fraction of P_hand a hand holds its ball (Table 1)")
      ->capture_default_str();
  cmd->add_option("--hand_separation", f->hand_separation,
                  "m between the hands' throw points, for Eq. 3 (assumed)")
      ->capture_default_str();
  cmd->add_flag("--transition", f->transition, "shortest transition: juggle siteswap --transition FROM TO");
  cmd->add_flag("--enumerate", f->enumerate, "list patterns (--balls, --max_throw, --period | --max_period)");
  cmd->add_option("--balls", f->balls, "--enumerate: number of balls");
  cmd->add_option("--max_throw", f->max_throw, "--enumerate: highest throw (0-35)");
  cmd->add_option("--period", f->period, "--enumerate: exact period (1-16)");
  cmd->add_option("--max_period", f->max_period,
                  "--enumerate: every period from 1 to this instead of --period");
  return [f] { return toss::RunSiteswapCommand(*f); };
}

}  // namespace juggle
