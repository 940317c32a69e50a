#include "common/flat_parameters.h"

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

FlatParameters Sample() {
  return *FlatParameters::Create(
      7, {{"a.w", {2, 3}}, {"a.b", {3}}, {"scalar", {}}},
      {1, 2, 3, 4, 5, 6, 0.5f, -0.5f, 0.25f, 42});
}

TEST(FlatParametersTest, SerializeDeserializeRoundTripsLayoutValuesAndVersion) {
  const FlatParameters p = Sample();
  absl::StatusOr<FlatParameters> q = FlatParameters::Deserialize(p.Serialize());
  ASSERT_TRUE(q.ok()) << q.status();
  EXPECT_EQ(q->version(), 7);
  EXPECT_EQ(q->values(), p.values());
  ASSERT_EQ(q->layout().size(), 3u);
  EXPECT_EQ(q->layout()[0].name, "a.w");
  EXPECT_EQ(q->layout()[0].shape, (std::vector<int64_t>{2, 3}));
  EXPECT_EQ(**q->Find("a.b", {3}), 0.5f);
  EXPECT_EQ(**q->Find("scalar", {}), 42.0f);
}

TEST(FlatParametersTest, CreateRejectsValueCountOtherThanTheLayouts) {
  const absl::StatusOr<FlatParameters> p = FlatParameters::Create(1, {{"x", {2, 2}}}, {1, 2, 3});
  EXPECT_EQ(p.status().code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(p.status().message(), HasSubstr("layout needs 4 values, got 3"));
}

TEST(FlatParametersTest, FindReportsMissingTensorsAndWrongShapes) {
  const FlatParameters p = Sample();
  EXPECT_EQ(p.Find("nope", {1}).status().code(), absl::StatusCode::kNotFound);
  const absl::Status s = p.Find("a.w", {3, 2}).status();
  EXPECT_EQ(s.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(s.message(), HasSubstr("has shape [2, 3], expected [3, 2]"));
}

TEST(FlatParametersTest, EveryTruncationIsDataLoss) {
  const std::string bytes = Sample().Serialize();
  for (size_t n = 0; n < bytes.size(); ++n) {
    EXPECT_EQ(FlatParameters::Deserialize(bytes.substr(0, n)).status().code(),
              absl::StatusCode::kDataLoss)
        << "prefix of " << n << " bytes";
  }
  EXPECT_THAT(FlatParameters::Deserialize(bytes + "x").status().message(),
              HasSubstr("trailing bytes"));
  std::string bad = bytes;
  bad[0] = 'X';
  EXPECT_THAT(FlatParameters::Deserialize(bad).status().message(), HasSubstr("bad magic"));
}

// Bytes of a snapshot header claiming `count` tensors, then `rest`.
std::string Header(uint32_t count, const std::string& rest) {
  std::string out = "JGLP";
  const uint32_t format = 1;
  const int64_t version = 0;
  out.append(reinterpret_cast<const char*>(&format), 4);
  out.append(reinterpret_cast<const char*>(&version), 8);
  out.append(reinterpret_cast<const char*>(&count), 4);
  return out + rest;
}

TEST(FlatParametersTest, AClaimedTensorCountBeyondTheBytesIsRefusedBeforeAllocating) {
  // 2^32 - 1 tensors would be 240 GB of layout entries.
  const absl::StatusOr<FlatParameters> p = FlatParameters::Deserialize(Header(0xffffffffu, "abc"));
  EXPECT_EQ(p.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(p.status().message(), HasSubstr("4294967295 tensors cannot fit in 3 bytes"));
}

TEST(FlatParametersTest, AShapeLargerThanTheDataIsRefusedWithoutOverflow) {
  // One tensor "t" of shape [2^31, 2^31, 2^31, 0]: the partial products overflow int64.
  std::string entry;
  const uint32_t len = 1;
  entry.append(reinterpret_cast<const char*>(&len), 4);
  entry += "t";
  entry += std::string(1, '\0') + std::string(1, '\4');
  for (int64_t d : {int64_t{1} << 31, int64_t{1} << 31, int64_t{1} << 31, int64_t{0}}) {
    entry.append(reinterpret_cast<const char*>(&d), 8);
  }
  const uint64_t n = 0;
  entry.append(reinterpret_cast<const char*>(&n), 8);
  const absl::StatusOr<FlatParameters> p = FlatParameters::Deserialize(Header(1, entry));
  EXPECT_EQ(p.status().code(), absl::StatusCode::kDataLoss);
  EXPECT_THAT(p.status().message(), HasSubstr("tensor 't' is larger than the data"));
}

}  // namespace
}  // namespace juggle
