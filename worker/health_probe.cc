#include "worker/health_probe.h"

#include <chrono>
#include <future>
#include <vector>

#include "absl/strings/str_cat.h"
#include "grpcpp/generic/generic_stub.h"
#include "grpcpp/grpcpp.h"

namespace juggle {
namespace {

// HealthCheckResponse{status: SERVING}: field 1 as a varint, value 1. No grpc.health.v1 stub is
// installed with Debian's gRPC, so the bytes are read by hand.
constexpr char kServingResponse[] = {0x08, 0x01};

absl::Status HealthCheckStatus(const grpc::Status& s, const std::string& address) {
  return absl::Status(static_cast<absl::StatusCode>(s.error_code()),
                      absl::StrCat("health check of ", address, ": ", s.error_message()));
}

}  // namespace

absl::Status ProbeLearnerHealth(const std::string& address, const TransportSecurity& security,
                                double timeout_s) {
  absl::StatusOr<std::shared_ptr<grpc::ChannelCredentials>> credentials =
      MakeChannelCredentials(security);
  if (!credentials.ok()) return credentials.status();
  grpc::ChannelArguments args;
  if (!security.server_name.empty()) args.SetSslTargetNameOverride(security.server_name);
  auto channel = grpc::CreateCustomChannel(address, *credentials, args);

  grpc::GenericStub stub(channel);
  grpc::ClientContext ctx;
  ctx.set_deadline(std::chrono::system_clock::now() +
                   std::chrono::microseconds(static_cast<int64_t>(timeout_s * 1e6)));
  grpc::Slice empty("");
  const grpc::ByteBuffer request(&empty, 1);  // HealthCheckRequest{service: ""}: no bytes
  grpc::ByteBuffer response;
  std::promise<grpc::Status> done;
  stub.UnaryCall(&ctx, "/grpc.health.v1.Health/Check", grpc::StubOptions(), &request, &response,
                 [&done](grpc::Status s) { done.set_value(std::move(s)); });
  const grpc::Status status = done.get_future().get();
  if (!status.ok()) return HealthCheckStatus(status, address);

  std::vector<grpc::Slice> slices;
  if (!response.Dump(&slices).ok()) return absl::InternalError("unreadable health response");
  std::string bytes;
  for (const grpc::Slice& s : slices) bytes.append(reinterpret_cast<const char*>(s.begin()), s.size());
  if (bytes != std::string(kServingResponse, sizeof(kServingResponse))) {
    return absl::UnavailableError(
        absl::StrCat("learner at ", address, " is not SERVING (", bytes.size(), " response bytes)"));
  }
  return absl::OkStatus();
}

}  // namespace juggle
