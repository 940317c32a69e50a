#include "play/play_commands.h"

#include <cmath>
#include <set>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "nlohmann/json.hpp"

namespace juggle::play {
namespace {

using Json = nlohmann::json;

struct CommandInfo {
  const char* name;
  CommandKind kind;
  std::vector<const char*> fields;  // besides "cmd"
};

const std::vector<CommandInfo>& Commands() {
  static const auto* commands = new std::vector<CommandInfo>{
      {"pause", CommandKind::kPause, {}},
      {"resume", CommandKind::kResume, {}},
      {"speed", CommandKind::kSpeed, {"factor"}},
      {"restart", CommandKind::kRestart, {"seed"}},
      {"poke", CommandKind::kPoke, {"impulse"}},
      {"skill", CommandKind::kSkill, {"node"}},
      {"pattern", CommandKind::kPattern, {"siteswap"}},
      {"wind", CommandKind::kWind, {"newtons"}},
      {"claim", CommandKind::kClaim, {}},
      {"release", CommandKind::kRelease, {}},
      {"step", CommandKind::kStep, {"steps"}},
  };
  return *commands;
}

absl::Status Refuse(const std::string& message) { return absl::InvalidArgumentError(message); }

absl::StatusOr<double> Number(const Json& object, const std::string& cmd, const char* field,
                              double lo, double hi) {
  auto it = object.find(field);
  if (it == object.end()) return Refuse(absl::StrCat(cmd, ": \"", field, "\" is missing"));
  if (!it->is_number()) return Refuse(absl::StrCat(cmd, ": \"", field, "\" must be a number"));
  const double v = it->get<double>();
  if (!std::isfinite(v) || v < lo || v > hi) {
    return Refuse(absl::StrFormat("%s: \"%s\" must lie in [%g, %g], not %g", cmd, field, lo, hi,
                                  v));
  }
  return v;
}

absl::StatusOr<std::string> Name(const Json& object, const std::string& cmd, const char* field) {
  auto it = object.find(field);
  if (it == object.end()) return Refuse(absl::StrCat(cmd, ": \"", field, "\" is missing"));
  if (!it->is_string()) return Refuse(absl::StrCat(cmd, ": \"", field, "\" must be a string"));
  std::string name = it->get<std::string>();
  if (name.empty() || name.size() > 64) {
    return Refuse(absl::StrCat(cmd, ": \"", field, "\" must have 1 to 64 characters"));
  }
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) {
      return Refuse(absl::StrCat(cmd, ": \"", field, "\" may hold letters, digits, _ and - only"));
    }
  }
  return name;
}

}  // namespace

const char* CommandName(CommandKind kind) {
  for (const CommandInfo& c : Commands()) {
    if (c.kind == kind) return c.name;
  }
  return "?";
}

absl::StatusOr<PlayCommand> ParsePlayCommand(const std::string& text,
                                             const CommandLimits& limits) {
  if (text.size() > limits.max_bytes) {
    return Refuse(absl::StrCat("the command has ", text.size(), " bytes; at most ",
                               limits.max_bytes, " are read"));
  }
  const Json object = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (object.is_discarded()) return Refuse("the command is not valid JSON");
  if (!object.is_object()) return Refuse("the command must be a JSON object with a \"cmd\"");
  auto cmd_it = object.find("cmd");
  if (cmd_it == object.end() || !cmd_it->is_string()) {
    return Refuse("the command has no \"cmd\" string");
  }
  const std::string cmd = cmd_it->get<std::string>();
  const CommandInfo* info = nullptr;
  std::vector<std::string> known;
  for (const CommandInfo& c : Commands()) {
    known.push_back(c.name);
    if (cmd == c.name) info = &c;
  }
  if (info == nullptr) {
    return Refuse(absl::StrCat("unknown command \"", cmd.substr(0, 32), "\" (known: ",
                               absl::StrJoin(known, ", "), ")"));
  }
  for (const auto& [key, value] : object.items()) {
    if (key == "cmd") continue;
    bool taken = false;
    for (const char* f : info->fields) taken = taken || key == f;
    if (!taken) {
      return Refuse(absl::StrCat(cmd, " takes no field \"", key.substr(0, 32), "\""));
    }
  }
  PlayCommand c;
  c.kind = info->kind;
  switch (c.kind) {
    case CommandKind::kSpeed: {
      absl::StatusOr<double> f = Number(object, cmd, "factor", limits.min_speed, limits.max_speed);
      if (!f.ok()) return f.status();
      c.factor = *f;
      break;
    }
    case CommandKind::kRestart:
      if (object.contains("seed")) {
        const Json& seed = object["seed"];
        if (!seed.is_number_unsigned() || seed.get<uint64_t>() > (uint64_t{1} << 48)) {
          return Refuse("restart: \"seed\" must be an integer in [0, 2^48]");
        }
        c.has_seed = true;
        c.seed = seed.get<uint64_t>();
      }
      break;
    case CommandKind::kPoke: {
      auto it = object.find("impulse");
      if (it == object.end()) return Refuse("poke: \"impulse\" is missing");
      if (!it->is_array() || it->size() != 3) {
        return Refuse("poke: \"impulse\" must be an array of 3 numbers (N·s, world x y z)");
      }
      double norm2 = 0;
      for (int k = 0; k < 3; ++k) {
        const Json& v = (*it)[k];
        if (!v.is_number() || !std::isfinite(v.get<double>())) {
          return Refuse("poke: \"impulse\" must be an array of 3 finite numbers");
        }
        c.impulse[k] = v.get<double>();
        norm2 += c.impulse[k] * c.impulse[k];
      }
      if (std::sqrt(norm2) > limits.max_impulse) {
        return Refuse(absl::StrFormat("poke: the impulse is %.3g N·s; at most %g N·s",
                                      std::sqrt(norm2), limits.max_impulse));
      }
      break;
    }
    case CommandKind::kSkill: {
      absl::StatusOr<std::string> name = Name(object, cmd, "node");
      if (!name.ok()) return name.status();
      c.name = *name;
      break;
    }
    case CommandKind::kPattern: {
      absl::StatusOr<std::string> name = Name(object, cmd, "siteswap");
      if (!name.ok()) return name.status();
      c.name = *name;
      break;
    }
    case CommandKind::kWind: {
      absl::StatusOr<double> n = Number(object, cmd, "newtons", -limits.max_wind, limits.max_wind);
      if (!n.ok()) return n.status();
      c.newtons = *n;
      break;
    }
    case CommandKind::kStep:
      if (object.contains("steps")) {
        const Json& n = object["steps"];
        if (!n.is_number_unsigned() || n.get<uint64_t>() < 1 || n.get<uint64_t>() > 100) {
          return Refuse("step: \"steps\" must be an integer in [1, 100]");
        }
        c.steps = static_cast<int>(n.get<uint64_t>());
      }
      break;
    default:
      break;
  }
  return c;
}

}  // namespace juggle::play
