// The `juggle` subcommands: each command file adds its CLI11 subcommand with typed, validated
// options (bound to state the returned body owns) and returns the body that runs after a
// successful parse. main.cc lists them once; `juggle --help` and the dispatch both come from
// that list. Exit codes: 0 ok, 1 the command failed (message on stderr), 2 a usage error
// (a malformed or out-of-range flag, a missing argument).
#ifndef JUGGLE_APP_COMMAND_H_
#define JUGGLE_APP_COMMAND_H_

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "absl/status/status.h"

namespace juggle {

// Runs after parsing; returns the process exit code.
using CommandBody = std::function<int()>;

struct Command {
  const char* name;
  const char* help;                  // the line in `juggle --help`
  CommandBody (*add)(CLI::App* cmd);  // adds options to `cmd`, returns the body bound to them
};

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

// Prints "error: <message>" to stderr; returns 1.
int Fail(const absl::Status& status);
// A usage error a command found itself: "error: <message>" and exit 2.
int UsageError(const std::string& message);

// Validators with short messages ("must be >= 1").
CLI::Validator AtLeast(double minimum);
CLI::Validator Between(double minimum, double maximum);

// Parses argv for `app` (with its subcommands added) and runs the chosen body. Help: printed,
// exit 0. Parse errors: "error: <which flag and why>" plus the command's --help hint, exit 2.
int ParseAndRun(CLI::App* app, int argc, char** argv, const CommandBody* const* bodies,
                CLI::App* const* subcommands, int count);

}  // namespace juggle

#endif  // JUGGLE_APP_COMMAND_H_
