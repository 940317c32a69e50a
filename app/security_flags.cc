#include "app/security_flags.h"

#include "app/command.h"

namespace juggle {

void AddSecurityFlags(CLI::App* cmd, SecurityRole role, SecurityFlags* f) {
  const bool learner = role == SecurityRole::kLearner;
  cmd->add_option("--token_file", f->token_file,
                  learner ? "file holding the token every RPC must carry (default: "
                            "$JUGGLE_TOKEN; neither: no token required)"
                          : "file holding the learner's token (default: $JUGGLE_TOKEN)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--tls_cert", f->tls.cert_file,
                  learner ? "PEM certificate chain of the learner: serve TLS"
                          : "PEM client certificate (mutual TLS; needs --tls_key, --tls_ca)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--tls_key", f->tls.key_file, "PEM private key of --tls_cert")
      ->check(CLI::ExistingFile);
  cmd->add_option("--tls_ca", f->tls.ca_file,
                  learner ? "PEM CA of client certificates: require mutual TLS"
                          : "PEM CA of the learner's certificate: connect with TLS")
      ->check(CLI::ExistingFile);
  if (!learner) {
    cmd->add_option("--tls_server_name", f->tls.server_name,
                    "name to verify in the learner's certificate (default: the --learner host)");
  }
}

absl::StatusOr<TransportSecurity> ResolveSecurity(const SecurityFlags& flags) {
  TransportSecurity security = flags.tls;
  absl::StatusOr<std::string> token = LoadToken(flags.token_file);
  if (!token.ok()) return token.status();
  security.token = *std::move(token);
  return security;
}

}  // namespace juggle
