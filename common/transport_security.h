// Authentication and encryption of the rollout service (docs/reliability.md): a shared token
// sent as "authorization: Bearer <token>" metadata on every RPC, and TLS (optionally mutual)
// with gRPC's SSL credentials. The token comes from a file or the JUGGLE_TOKEN environment
// variable, never from a flag (flags show in `ps`). Nothing set: plaintext without a token, as
// in local mode on loopback.
#ifndef JUGGLE_COMMON_TRANSPORT_SECURITY_H_
#define JUGGLE_COMMON_TRANSPORT_SECURITY_H_

#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "grpcpp/security/credentials.h"
#include "grpcpp/security/server_credentials.h"

namespace juggle {

struct TransportSecurity {
  std::string token;      // empty: no token required (learner) / sent (worker)
  // Learner: its certificate chain and key (both or neither: TLS). Worker: its client
  // certificate and key, for mutual TLS.
  std::string cert_file, key_file;
  // Learner: CA of client certificates; set, every client must present one it signed (mTLS).
  // Worker: CA of the learner's certificate; set, the worker connects with TLS.
  std::string ca_file;
  std::string server_name;  // worker: name to verify in the learner's certificate (optional)

  bool tls_server() const { return !cert_file.empty(); }
  bool tls_client() const { return !ca_file.empty(); }
};

// The metadata key of the token.
inline constexpr char kAuthorizationHeader[] = "authorization";

// The token from `token_file` if set (trailing newline stripped), else from $JUGGLE_TOKEN,
// else empty. NOT_FOUND for an unreadable file, INVALID_ARGUMENT for an empty or non-printable
// token.
absl::StatusOr<std::string> LoadToken(const std::string& token_file);

// Reads the files named by `security`'s TLS fields. INVALID_ARGUMENT for a key without a
// certificate (or the reverse) or mTLS without a server certificate; NOT_FOUND for a missing
// file (naming it).
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const TransportSecurity& security);
absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> MakeChannelCredentials(
    const TransportSecurity& security);

// "Bearer <token>" as a worker sends it.
std::string BearerValue(const std::string& token);
// True if `header` (the request's authorization metadata) carries `token`; compares in time
// independent of where they differ. An empty `token` accepts everything.
bool TokenMatches(const std::string& token, const std::string& header);

}  // namespace juggle

#endif  // JUGGLE_COMMON_TRANSPORT_SECURITY_H_
