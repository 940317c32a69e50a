// MergeOver and RebaseFileNames on RunConfig messages.
#include "common/config_merge.h"

#include <filesystem>

#include "google/protobuf/text_format.h"
#include "google/protobuf/util/message_differencer.h"
#include "gtest/gtest.h"
#include "proto/run_config.pb.h"

namespace juggle {
namespace {

config::RunConfig Parse(const std::string& text) {
  config::RunConfig run;
  EXPECT_TRUE(google::protobuf::TextFormat::ParseFromString(text, &run)) << text;
  return run;
}

TEST(MergeOverTest, DerivedFieldsReplaceTheBasesAndTheRestIsKept) {
  config::RunConfig base = Parse(
      "name: \"base\" seed: 3 model { num_experts: 8 hidden: 32 hidden: 32 } "
      "ppo { epochs: 2 num_minibatches: 4 }");
  MergeOver(Parse("name: \"derived\" model { hidden: 64 } ppo { epochs: 5 }"), &base);
  EXPECT_TRUE(google::protobuf::util::MessageDifferencer::Equals(
      base, Parse("name: \"derived\" seed: 3 model { num_experts: 8 hidden: 64 } "
                  "ppo { epochs: 5 num_minibatches: 4 }")))
      << base.ShortDebugString();
}

TEST(MergeOverTest, AnotherCaseOfAOneofReplacesTheBasesCase) {
  config::RunConfig base = Parse("soccer_juggle { graph_file: \"g.textproto\" }");
  MergeOver(Parse("toss { task: CATCH }"), &base);
  EXPECT_TRUE(base.has_toss());
  EXPECT_FALSE(base.has_soccer_juggle());
}

TEST(RebaseFileNamesTest, AnAbsentMessageWhoseDefaultNamesAFileIsRebasedToo) {
  config::RunConfig run = Parse("soccer_juggle { graph_file: \"g.textproto\" }");
  RebaseFileNames("configs", "configs/ablation", &run);
  EXPECT_EQ(run.soccer_juggle().env().model_file(), "../models/juggle_scene.xml");
  EXPECT_FALSE(run.has_toss());  // another case of the family oneof stays unset
}

TEST(RebaseFileNamesTest, RelativeNamesKeepNamingTheSameFilesFromTheNewFolder) {
  config::RunConfig run = Parse(
      "soccer_juggle { graph_file: \"graphs/a.textproto\" env { } }");
  RebaseFileNames("configs", "configs/learning", &run);
  EXPECT_EQ(run.soccer_juggle().graph_file(), "../graphs/a.textproto");
  // A default file name of a present message is rebased too, and made explicit.
  EXPECT_TRUE(run.soccer_juggle().env().has_model_file());
  EXPECT_EQ(run.soccer_juggle().env().model_file(), "../models/juggle_scene.xml");
}

TEST(RebaseFileNamesTest, AbsoluteNamesAndTheSameFolderAreLeftAlone) {
  config::RunConfig run = Parse("soccer_juggle { graph_file: \"/abs/g.textproto\" env { } }");
  RebaseFileNames("configs", "configs/learning", &run);
  EXPECT_EQ(run.soccer_juggle().graph_file(), "/abs/g.textproto");
  config::RunConfig same = Parse("soccer_juggle { graph_file: \"g.textproto\" env { } }");
  RebaseFileNames("configs", "configs/.", &same);
  EXPECT_EQ(same.soccer_juggle().graph_file(), "g.textproto");
  EXPECT_FALSE(same.soccer_juggle().env().has_model_file());
}

TEST(RebaseFileNamesTest, ABaseInAnAbsoluteFolderKeepsNamingItsFilesFromARelativeOne) {
  const std::string cwd = std::filesystem::current_path().string();
  config::RunConfig run = Parse("soccer_juggle { graph_file: \"graphs/a.textproto\" env { } }");
  RebaseFileNames(cwd + "/configs", "runs/search", &run);
  EXPECT_EQ(run.soccer_juggle().graph_file(), "../../configs/graphs/a.textproto");
  EXPECT_EQ(run.soccer_juggle().env().model_file(), "../../configs/models/juggle_scene.xml");
  config::RunConfig back = Parse("soccer_juggle { graph_file: \"a.textproto\" }");
  RebaseFileNames("configs", cwd + "/runs", &back);
  EXPECT_EQ(back.soccer_juggle().graph_file(), "../configs/a.textproto");
}

}  // namespace
}  // namespace juggle
