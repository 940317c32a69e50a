// The commands the live page (`juggle play`, docs/play.md) sends to the server, parsed and
// checked before anything acts on them: one JSON object per POST to /api/command, e.g.
//   {"cmd": "poke", "impulse": [0.3, 0, 0.5]}   an impulse on the ball (N·s)
//   {"cmd": "skill", "node": "head_down"}        the next skill: a graph node ("walk": the
//                                                 adaptive walk chooses again)
//   {"cmd": "pattern", "siteswap": "531"}        toss: the next siteswap
//   {"cmd": "wind", "newtons": 0.5}              toss: wind on the balls in flight
//   {"cmd": "pause"} {"cmd": "resume"} {"cmd": "speed", "factor": 0.25}
//   {"cmd": "step"} {"cmd": "step", "steps": 5}  while paused: control steps, one at a time
//   {"cmd": "restart"} (a new start) {"cmd": "restart", "seed": 7}
//   {"cmd": "claim"} {"cmd": "release"}          take or give up control (one controller)
// Every field is typed and bounded here; what depends on the world (a node the graph has, an
// edge it allows) is checked by the world (play/play_world.h). Pure; thread-safe.
#ifndef JUGGLE_PLAY_PLAY_COMMANDS_H_
#define JUGGLE_PLAY_PLAY_COMMANDS_H_

#include <array>
#include <cstdint>
#include <string>

#include "absl/status/statusor.h"

namespace juggle::play {

enum class CommandKind {
  kPause,
  kResume,
  kSpeed,
  kRestart,
  kPoke,
  kSkill,
  kPattern,
  kWind,
  kClaim,
  kRelease,
  kStep,
};

struct PlayCommand {
  CommandKind kind = CommandKind::kPause;
  double factor = 1;                      // kSpeed: simulated seconds per wall second
  bool has_seed = false;                  // kRestart
  uint64_t seed = 0;
  std::array<double, 3> impulse{};        // kPoke: N·s, world axes
  std::string name;                       // kSkill: node; kPattern: siteswap
  double newtons = 0;                     // kWind
  int steps = 1;                          // kStep: 1..100
};

struct CommandLimits {
  size_t max_bytes = 4096;       // a longer message is refused before it is parsed
  double max_impulse = 2.0;      // N·s, the poke's largest magnitude
  double max_wind = 2.0;         // N, the largest wind magnitude
  double min_speed = 0.05;       // the speed factor's range
  double max_speed = 4.0;
};

// The command `text` holds. INVALID_ARGUMENT with a message for the page: too long, not JSON,
// not an object, no or an unknown "cmd", a missing, mistyped, non-finite or out-of-range field,
// or a field the command does not take.
absl::StatusOr<PlayCommand> ParsePlayCommand(const std::string& text,
                                             const CommandLimits& limits = {});

// "poke", "skill", ...: the command's name as the page writes it.
const char* CommandName(CommandKind kind);

}  // namespace juggle::play

#endif  // JUGGLE_PLAY_PLAY_COMMANDS_H_
