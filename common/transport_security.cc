#include "common/transport_security.h"

#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "common/file_io.h"

namespace juggle {
namespace {

absl::StatusOr<std::string> ReadWholeFile(const std::string& path, const std::string& what) {
  absl::StatusOr<std::string> bytes = ReadFile(path);
  if (!bytes.ok()) {
    return absl::Status(bytes.status().code(),
                        absl::StrCat(what, ": ", bytes.status().message()));
  }
  return bytes;
}

absl::Status CheckPair(const TransportSecurity& s) {
  if (s.cert_file.empty() != s.key_file.empty()) {
    return absl::InvalidArgumentError(
        "TLS: give both a certificate (--tls_cert) and its key (--tls_key), or neither");
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::string> LoadToken(const std::string& token_file) {
  std::string token;
  std::string source;
  if (!token_file.empty()) {
    absl::StatusOr<std::string> text = ReadWholeFile(token_file, "token file");
    if (!text.ok()) return text.status();
    token = *std::move(text);
    source = token_file;
  } else if (const char* env = std::getenv("JUGGLE_TOKEN"); env != nullptr) {
    token = env;
    source = "$JUGGLE_TOKEN";
  } else {
    return std::string();
  }
  while (!token.empty() && (token.back() == '\n' || token.back() == '\r')) token.pop_back();
  if (token.empty()) return absl::InvalidArgumentError(absl::StrCat("the token in ", source, " is empty"));
  for (char c : token) {
    if (c < 0x21 || c > 0x7e) {
      return absl::InvalidArgumentError(absl::StrCat(
          "the token in ", source, " must be printable ASCII without spaces"));
    }
  }
  return token;
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const TransportSecurity& s) {
  if (absl::Status pair = CheckPair(s); !pair.ok()) return pair;
  if (!s.tls_server()) {
    if (s.tls_client()) {
      return absl::InvalidArgumentError(
          "TLS: a client CA (--tls_ca, mutual TLS) needs the learner's own certificate "
          "(--tls_cert, --tls_key)");
    }
    return grpc::InsecureServerCredentials();
  }
  grpc::SslServerCredentialsOptions options(
      s.tls_client() ? GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY
                     : GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE);
  grpc::SslServerCredentialsOptions::PemKeyCertPair pair;
  absl::StatusOr<std::string> cert = ReadWholeFile(s.cert_file, "TLS certificate");
  if (!cert.ok()) return cert.status();
  absl::StatusOr<std::string> key = ReadWholeFile(s.key_file, "TLS key");
  if (!key.ok()) return key.status();
  pair.cert_chain = *std::move(cert);
  pair.private_key = *std::move(key);
  options.pem_key_cert_pairs.push_back(std::move(pair));
  if (s.tls_client()) {
    absl::StatusOr<std::string> ca = ReadWholeFile(s.ca_file, "client CA");
    if (!ca.ok()) return ca.status();
    options.pem_root_certs = *std::move(ca);
  }
  return grpc::SslServerCredentials(options);
}

absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> MakeChannelCredentials(
    const TransportSecurity& s) {
  if (absl::Status pair = CheckPair(s); !pair.ok()) return pair;
  if (!s.tls_client()) {
    if (s.tls_server()) {
      return absl::InvalidArgumentError(
          "TLS: a client certificate (--tls_cert) needs the learner's CA (--tls_ca)");
    }
    return grpc::InsecureChannelCredentials();
  }
  grpc::SslCredentialsOptions options;
  absl::StatusOr<std::string> ca = ReadWholeFile(s.ca_file, "TLS CA");
  if (!ca.ok()) return ca.status();
  options.pem_root_certs = *std::move(ca);
  if (s.tls_server()) {
    absl::StatusOr<std::string> cert = ReadWholeFile(s.cert_file, "TLS certificate");
    if (!cert.ok()) return cert.status();
    absl::StatusOr<std::string> key = ReadWholeFile(s.key_file, "TLS key");
    if (!key.ok()) return key.status();
    options.pem_cert_chain = *std::move(cert);
    options.pem_private_key = *std::move(key);
  }
  return grpc::SslCredentials(options);
}

std::string BearerValue(const std::string& token) { return absl::StrCat("Bearer ", token); }

bool TokenMatches(const std::string& token, const std::string& header) {
  if (token.empty()) return true;
  const std::string expected = BearerValue(token);
  // Length is not secret; the bytes are compared without an early exit.
  if (header.size() != expected.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < expected.size(); ++i) {
    diff |= static_cast<unsigned char>(header[i] ^ expected[i]);
  }
  return diff == 0;
}

}  // namespace juggle
