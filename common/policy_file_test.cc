// common/policy_file: the exported-policy container — round trip, format-1 files, and every way
// a file can be damaged (truncated anywhere, a flipped byte, a hostile size, a newer format).
#include "common/policy_file.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>

#include "common/file_io.h"
#include "common/testing/temp_dir.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

// A complete format-2 policy with made-up contents (nothing here runs it).
config::ExportedPolicy CompletePolicy() {
  config::ExportedPolicy p;
  p.set_obs_dim(3);
  p.set_act_dim(2);
  p.set_parameters(std::string(200, 'p'));
  p.set_source("runs/x/checkpoints/ckpt-0000000001.jglc");
  p.set_run_config("seed: 7\n");
  p.set_config_path("configs/x.textproto");
  p.set_model_mjb(std::string(300, 'm'));
  p.set_mujoco_version(222);
  return p;
}

TEST(PolicyFileTest, WriteThenReadGivesTheSamePolicyAsFormat2) {
  const std::string path = MakeTempDir("juggle_policy_file_") + "/p.jglpolicy";
  ASSERT_TRUE(WritePolicyFile(path, CompletePolicy()).ok());
  absl::StatusOr<PolicyFile> read = ReadPolicyFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->format, 2);
  EXPECT_EQ(read->policy.SerializeAsString(), CompletePolicy().SerializeAsString());
  EXPECT_EQ(ReadFile(path)->substr(0, 8), "JGLPOLCY");
}

TEST(PolicyFileTest, BareProtobufIsReadAsFormat1) {
  config::ExportedPolicy old = CompletePolicy();
  old.clear_model_mjb();
  old.clear_mujoco_version();
  absl::StatusOr<PolicyFile> read = ParsePolicyFile(old.SerializeAsString(), "old.jglpolicy");
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(read->format, 1);
  EXPECT_EQ(read->policy.config_path(), "configs/x.textproto");
}

TEST(PolicyFileTest, EveryTruncationIsAnErrorNamingTheFile) {
  const std::string bytes = SerializePolicyFile(CompletePolicy());
  for (size_t n = 0; n < bytes.size(); ++n) {
    const absl::StatusOr<PolicyFile> read = ParsePolicyFile(bytes.substr(0, n), "cut.jglpolicy");
    ASSERT_FALSE(read.ok()) << "a file cut to " << n << " of " << bytes.size() << " bytes loaded";
    EXPECT_EQ(read.status().code(), absl::StatusCode::kDataLoss) << n;
    EXPECT_THAT(read.status().message(), HasSubstr("cut.jglpolicy")) << n;
  }
  const size_t payload = CompletePolicy().ByteSizeLong();  // after a 28-byte header
  ASSERT_EQ(bytes.size(), 28 + payload);
  EXPECT_EQ(ParsePolicyFile(bytes.substr(0, bytes.size() - 1), "cut.jglpolicy").status().message(),
            "cut.jglpolicy: exported policy truncated or padded: its payload has " +
                std::to_string(payload - 1) + " of " + std::to_string(payload) + " bytes");
}

TEST(PolicyFileTest, AFlippedPayloadByteFailsTheChecksum) {
  std::string bytes = SerializePolicyFile(CompletePolicy());
  bytes[bytes.size() - 100] ^= 0x10;
  const absl::StatusOr<PolicyFile> read = ParsePolicyFile(bytes, "flip.jglpolicy");
  EXPECT_EQ(read.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(read.status().message(),
            "flip.jglpolicy: exported policy corrupted: checksum mismatch");
}

TEST(PolicyFileTest, AHugeClaimedSizeIsRefusedBeforeAnythingIsCopied) {
  std::string bytes = SerializePolicyFile(CompletePolicy());
  const uint64_t huge = uint64_t{1} << 62;
  std::memcpy(bytes.data() + 12, &huge, sizeof(huge));
  const absl::StatusOr<PolicyFile> read = ParsePolicyFile(bytes, "huge.jglpolicy");
  EXPECT_EQ(read.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(read.status().message(), HasSubstr("of 4611686018427387904 bytes"));
}

TEST(PolicyFileTest, ANewerFormatIsRefusedNamingIt) {
  std::string bytes = SerializePolicyFile(CompletePolicy());
  const uint32_t three = 3;
  std::memcpy(bytes.data() + 8, &three, sizeof(three));
  const absl::StatusOr<PolicyFile> read = ParsePolicyFile(bytes, "new.jglpolicy");
  EXPECT_EQ(read.status().code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(read.status().message(), HasSubstr("format 3, written by a newer juggle"));
}

TEST(PolicyFileTest, AFormat2FileWithoutItsModelIsIncompleteAndCannotBeWritten) {
  config::ExportedPolicy p = CompletePolicy();
  p.clear_model_mjb();
  const absl::StatusOr<PolicyFile> read = ParsePolicyFile(SerializePolicyFile(p), "x.jglpolicy");
  EXPECT_EQ(read.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_EQ(read.status().message(),
            "x.jglpolicy: exported policy incomplete: it has no compiled model");
  const std::string path = MakeTempDir("juggle_policy_file_") + "/p.jglpolicy";
  const absl::Status written = WritePolicyFile(path, p);
  EXPECT_EQ(written.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_EQ(ReadFile(path).status().code(), absl::StatusCode::kNotFound);
}

TEST(PolicyFileTest, TextIsNotAPolicy) {
  const absl::StatusOr<PolicyFile> read =
      ParsePolicyFile("state { angle: [0, 1, -2, 0.5] }\n", "t.jglpolicy");
  EXPECT_EQ(read.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(read.status().message(), HasSubstr("juggle export-policy"));
}

}  // namespace
}  // namespace juggle
