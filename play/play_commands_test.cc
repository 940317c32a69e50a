// The page's commands: each well-formed command parses to its fields; malformed JSON, non-objects,
// unknown commands and fields, wrong types, non-finite and out-of-range values and oversized
// messages are refused with a message naming what is wrong.
#include "play/play_commands.h"

#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle::play {
namespace {

using ::testing::HasSubstr;

std::string Refusal(const std::string& text, const CommandLimits& limits = {}) {
  absl::StatusOr<PlayCommand> c = ParsePlayCommand(text, limits);
  EXPECT_FALSE(c.ok()) << text;
  if (c.ok()) return "";
  EXPECT_EQ(c.status().code(), absl::StatusCode::kInvalidArgument);
  return std::string(c.status().message());
}

TEST(PlayCommandsTest, ParsesEveryCommandWithItsFields) {
  absl::StatusOr<PlayCommand> poke = ParsePlayCommand(R"({"cmd":"poke","impulse":[0.1,-0.2,0.5]})");
  ASSERT_TRUE(poke.ok()) << poke.status();
  EXPECT_EQ(poke->kind, CommandKind::kPoke);
  EXPECT_DOUBLE_EQ(poke->impulse[1], -0.2);
  EXPECT_DOUBLE_EQ(poke->impulse[2], 0.5);
  absl::StatusOr<PlayCommand> skill = ParsePlayCommand(R"({"cmd":"skill","node":"head_down"})");
  ASSERT_TRUE(skill.ok());
  EXPECT_EQ(skill->kind, CommandKind::kSkill);
  EXPECT_EQ(skill->name, "head_down");
  absl::StatusOr<PlayCommand> speed = ParsePlayCommand(R"({"cmd":"speed","factor":0.25})");
  ASSERT_TRUE(speed.ok());
  EXPECT_DOUBLE_EQ(speed->factor, 0.25);
  absl::StatusOr<PlayCommand> restart = ParsePlayCommand(R"({"cmd":"restart","seed":7})");
  ASSERT_TRUE(restart.ok());
  EXPECT_TRUE(restart->has_seed);
  EXPECT_EQ(restart->seed, 7u);
  EXPECT_FALSE(ParsePlayCommand(R"({"cmd":"restart"})")->has_seed);
  EXPECT_EQ(ParsePlayCommand(R"({"cmd":"pattern","siteswap":"531"})")->name, "531");
  EXPECT_DOUBLE_EQ(ParsePlayCommand(R"({"cmd":"wind","newtons":-0.5})")->newtons, -0.5);
  EXPECT_EQ(ParsePlayCommand(R"({"cmd":"step","steps":5})")->steps, 5);
  EXPECT_EQ(ParsePlayCommand(R"({"cmd":"step"})")->steps, 1);
  for (const char* name : {"pause", "resume", "claim", "release"}) {
    absl::StatusOr<PlayCommand> c = ParsePlayCommand(std::string(R"({"cmd":")") + name + "\"}");
    ASSERT_TRUE(c.ok()) << name;
    EXPECT_STREQ(CommandName(c->kind), name);
  }
}

TEST(PlayCommandsTest, RefusesMalformedJsonAndNonObjects) {
  EXPECT_THAT(Refusal("{\"cmd\": \"poke\""), HasSubstr("not valid JSON"));
  EXPECT_THAT(Refusal(""), HasSubstr("not valid JSON"));
  EXPECT_THAT(Refusal("[1,2]"), HasSubstr("JSON object"));
  EXPECT_THAT(Refusal("\"pause\""), HasSubstr("JSON object"));
  EXPECT_THAT(Refusal("{}"), HasSubstr("no \"cmd\""));
  EXPECT_THAT(Refusal(R"({"cmd": 3})"), HasSubstr("no \"cmd\""));
}

TEST(PlayCommandsTest, RefusesUnknownCommandsAndFieldsNamingThem) {
  EXPECT_THAT(Refusal(R"({"cmd":"explode"})"), HasSubstr("unknown command \"explode\""));
  EXPECT_THAT(Refusal(R"({"cmd":"explode"})"), HasSubstr("poke"));
  EXPECT_THAT(Refusal(R"({"cmd":"pause","speed":2})"), HasSubstr("pause takes no field \"speed\""));
}

TEST(PlayCommandsTest, RefusesMistypedMissingNonFiniteAndOutOfRangeValues) {
  EXPECT_THAT(Refusal(R"({"cmd":"poke"})"), HasSubstr("\"impulse\" is missing"));
  EXPECT_THAT(Refusal(R"({"cmd":"poke","impulse":[1,2]})"), HasSubstr("array of 3"));
  EXPECT_THAT(Refusal(R"({"cmd":"poke","impulse":[1,"a",2]})"), HasSubstr("finite"));
  EXPECT_THAT(Refusal(R"({"cmd":"poke","impulse":[1e400,0,0]})"), HasSubstr("not valid JSON"));
  EXPECT_THAT(Refusal(R"({"cmd":"poke","impulse":[2,2,0]})"), HasSubstr("at most 2 N·s"));
  EXPECT_THAT(Refusal(R"({"cmd":"speed","factor":"fast"})"), HasSubstr("must be a number"));
  EXPECT_THAT(Refusal(R"({"cmd":"speed","factor":100})"), HasSubstr("[0.05, 4]"));
  EXPECT_THAT(Refusal(R"({"cmd":"speed","factor":0})"), HasSubstr("[0.05, 4]"));
  EXPECT_THAT(Refusal(R"({"cmd":"wind","newtons":3})"), HasSubstr("[-2, 2]"));
  EXPECT_THAT(Refusal(R"({"cmd":"restart","seed":-1})"), HasSubstr("integer"));
  EXPECT_THAT(Refusal(R"({"cmd":"step","steps":0})"), HasSubstr("[1, 100]"));
  EXPECT_THAT(Refusal(R"({"cmd":"step","steps":101})"), HasSubstr("[1, 100]"));
  EXPECT_THAT(Refusal(R"({"cmd":"restart","seed":1.5})"), HasSubstr("integer"));
  EXPECT_THAT(Refusal(R"({"cmd":"skill","node":7})"), HasSubstr("must be a string"));
  EXPECT_THAT(Refusal(R"({"cmd":"skill","node":""})"), HasSubstr("1 to 64"));
  EXPECT_THAT(Refusal(R"({"cmd":"skill","node":"a<script>"})"), HasSubstr("letters, digits"));
}

TEST(PlayCommandsTest, RefusesMessagesLongerThanTheLimitBeforeParsing) {
  CommandLimits limits;
  limits.max_bytes = 64;
  const std::string huge = R"({"cmd":"skill","node":")" + std::string(100, 'a') + "\"}";
  EXPECT_THAT(Refusal(huge, limits), HasSubstr("at most 64 are read"));
  EXPECT_THAT(Refusal(std::string(1 << 20, '['), CommandLimits{}), HasSubstr("at most 4096"));
}

}  // namespace
}  // namespace juggle::play
