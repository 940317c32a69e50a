// The transport-security flags of `juggle learner` and `juggle worker`: where the token and the
// TLS files are. The token itself is never a flag (it would show in `ps`): --token_file, or the
// JUGGLE_TOKEN environment variable.
#ifndef JUGGLE_APP_SECURITY_FLAGS_H_
#define JUGGLE_APP_SECURITY_FLAGS_H_

#include <CLI/CLI.hpp>

#include "absl/status/statusor.h"
#include "common/transport_security.h"

namespace juggle {

struct SecurityFlags {
  std::string token_file;
  TransportSecurity tls;  // file names only; the token is filled in by ResolveSecurity
};

enum class SecurityRole { kLearner, kWorker };
void AddSecurityFlags(CLI::App* cmd, SecurityRole role, SecurityFlags* flags);
// The TransportSecurity the flags describe, with the token loaded. Errors name the file.
absl::StatusOr<TransportSecurity> ResolveSecurity(const SecurityFlags& flags);

}  // namespace juggle

#endif  // JUGGLE_APP_SECURITY_FLAGS_H_
