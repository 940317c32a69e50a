// common/file_io: whole-file reads and checked writes, on real files, a full device
// (/dev/full) and a read-only folder.
#include "common/file_io.h"

#include <sys/stat.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/testing/temp_dir.h"
#include "common/testing/unprivileged.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"

namespace juggle {
namespace {

using ::testing::HasSubstr;

TEST(FileIoTest, WriteFileThenReadFileGivesTheBytesBack) {
  const std::string path = MakeTempDir("juggle_file_io_") + "/a.bin";
  const std::string bytes("one\0two\nthree", 13);
  ASSERT_TRUE(WriteFile(path, bytes).ok());
  absl::StatusOr<std::string> read = ReadFile(path);
  ASSERT_TRUE(read.ok()) << read.status();
  EXPECT_EQ(*read, bytes);
  ASSERT_TRUE(WriteFile(path, "short").ok());  // truncates
  EXPECT_EQ(*ReadFile(path), "short");
}

TEST(FileIoTest, ReadFileNamesTheMissingFileAndRefusesFoldersAndDevices) {
  const std::string dir = MakeTempDir("juggle_file_io_");
  absl::StatusOr<std::string> missing = ReadFile(dir + "/none.txt");
  EXPECT_EQ(missing.status().code(), absl::StatusCode::kNotFound);
  EXPECT_EQ(missing.status().message(),
            dir + "/none.txt: cannot open file (No such file or directory)");
  EXPECT_EQ(ReadFile(dir).status().message(), dir + ": is a directory");
  EXPECT_EQ(ReadFile("/dev/zero").status().message(), "/dev/zero: is not a regular file");
}

TEST(FileIoTest, WritesToAFullDeviceAreResourceExhausted) {
  const absl::Status whole = WriteFile("/dev/full", "x");
  EXPECT_EQ(whole.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(whole.message(), "cannot write /dev/full: No space left on device");
  absl::StatusOr<std::unique_ptr<AppendFile>> file = AppendFile::Open("/dev/full");
  ASSERT_TRUE(file.ok()) << file.status();
  const absl::Status appended = (*file)->Append("a line\n");
  EXPECT_EQ(appended.code(), absl::StatusCode::kResourceExhausted);
  EXPECT_EQ(appended.message(), "cannot write /dev/full: No space left on device");
}

TEST(FileIoTest, AppendFileAddsToTheEndOfAnExistingFile) {
  const std::string path = MakeTempDir("juggle_file_io_") + "/log.jsonl";
  ASSERT_TRUE(WriteFile(path, "first\n").ok());
  absl::StatusOr<std::unique_ptr<AppendFile>> file = AppendFile::Open(path);
  ASSERT_TRUE(file.ok()) << file.status();
  ASSERT_TRUE((*file)->Append("second\n").ok());
  ASSERT_TRUE((*file)->Append("third\n").ok());
  EXPECT_EQ(*ReadFile(path), "first\nsecond\nthird\n");
}

TEST(FileIoTest, WritesIntoAReadOnlyFolderArePermissionDenied) {
  const std::string dir = MakeTempDir("juggle_file_io_");
  ASSERT_EQ(::chmod(dir.c_str(), 0555), 0);
  // In a child that is not root (root ignores the folder's mode).
  EXPECT_EXIT(
      {
        DropRootPrivileges();
        const absl::Status whole = WriteFile(dir + "/a.txt", "x");
        const absl::Status atomic = WriteFileAtomically(dir + "/b.txt", "x");
        const absl::Status appended = AppendFile::Open(dir + "/c.jsonl").status();
        const absl::Status checked = CheckWritable(dir + "/d.txt");
        std::fprintf(stderr, "%s\n%s\n%s\n%s\n", whole.ToString().c_str(),
                     atomic.ToString().c_str(), appended.ToString().c_str(),
                     checked.ToString().c_str());
        std::exit(whole.code() == absl::StatusCode::kPermissionDenied &&
                          atomic.code() == absl::StatusCode::kPermissionDenied &&
                          appended.code() == absl::StatusCode::kPermissionDenied &&
                          checked.code() == absl::StatusCode::kPermissionDenied
                      ? 0
                      : 1);
      },
      ::testing::ExitedWithCode(0),
      "cannot write .*/a.txt: Permission denied\n.*cannot write .*/b.txt.tmp: Permission "
      "denied\n.*cannot open for appending .*/c.jsonl: Permission denied\n.*cannot write "
      ".*/d.txt: Permission denied");
}

TEST(FileIoTest, WriteFileAtomicallyReplacesTheFileAndLeavesNoTemporary) {
  const std::string dir = MakeTempDir("juggle_file_io_");
  ASSERT_TRUE(WriteFileAtomically(dir + "/c.bin", "old").ok());
  ASSERT_TRUE(WriteFileAtomically(dir + "/c.bin", "new").ok());
  EXPECT_EQ(*ReadFile(dir + "/c.bin"), "new");
  EXPECT_EQ(ReadFile(dir + "/c.bin.tmp").status().code(), absl::StatusCode::kNotFound);
}

TEST(FileIoTest, CheckWritableLeavesNoTraceAndKeepsExistingFiles) {
  const std::string dir = MakeTempDir("juggle_file_io_");
  ASSERT_TRUE(CheckWritable(dir + "/new.txt").ok());
  EXPECT_EQ(ReadFile(dir + "/new.txt").status().code(), absl::StatusCode::kNotFound);
  ASSERT_TRUE(WriteFile(dir + "/old.txt", "kept").ok());
  ASSERT_TRUE(CheckWritable(dir + "/old.txt").ok());
  EXPECT_EQ(*ReadFile(dir + "/old.txt"), "kept");
  EXPECT_EQ(CheckWritable("").code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(std::string(CheckWritable("/nonexistent-dir/x").message()),
              HasSubstr("cannot write /nonexistent-dir/x: No such file or directory"));
}

}  // namespace
}  // namespace juggle
