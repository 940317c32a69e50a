#include "app/command.h"

#include <cstdio>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace juggle {

int Fail(const absl::Status& status) {
  std::fprintf(stderr, "error: %s\n", std::string(status.message()).c_str());
  return kExitFailure;
}

int UsageError(const std::string& message) {
  std::fprintf(stderr, "error: %s\n", message.c_str());
  return kExitUsage;
}

CLI::Validator AtLeast(double minimum) {
  return CLI::Validator(
      [minimum](std::string& value) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v)) return absl::StrCat("'", value, "' is not a number");
        return v >= minimum ? "" : absl::StrCat("must be >= ", minimum, ", got ", value);
      },
      absl::StrCat(">=", minimum));
}

CLI::Validator Between(double minimum, double maximum) {
  return CLI::Validator(
      [minimum, maximum](std::string& value) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v)) return absl::StrCat("'", value, "' is not a number");
        return v >= minimum && v <= maximum
                   ? ""
                   : absl::StrCat("must lie in [", minimum, ", ", maximum, "], got ", value);
      },
      absl::StrFormat("[%g,%g]", minimum, maximum));
}

int ParseAndRun(CLI::App* app, int argc, char** argv, const CommandBody* const* bodies,
                CLI::App* const* subcommands, int count) {
  if (argc > 1 && argv[1][0] != '-') {
    bool known = false;
    for (int i = 0; i < count; ++i) known |= subcommands[i]->get_name() == argv[1];
    if (!known) {
      std::fprintf(stderr, "error: unknown command '%s' (see juggle --help)\n", argv[1]);
      return kExitUsage;
    }
  }
  try {
    app->parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app->exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app->exit(e);
  } catch (const CLI::ParseError& e) {
    std::string hint = "juggle --help";
    for (int i = 0; i < count; ++i) {
      if (subcommands[i]->parsed()) hint = absl::StrCat("juggle ", subcommands[i]->get_name(), " --help");
    }
    std::fprintf(stderr, "error: %s (see %s)\n", e.what(), hint.c_str());
    return kExitUsage;
  }
  for (int i = 0; i < count; ++i) {
    if (subcommands[i]->parsed()) return (*bodies[i])();
  }
  std::fprintf(stderr, "error: no command given (see juggle --help)\n");
  return kExitUsage;
}

}  // namespace juggle
