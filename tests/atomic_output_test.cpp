// Outputs are written atomically (issue 16): a writer killed mid-write (SIGKILL, no destructor
// runs) leaves the previous file intact; a clean exit or an abandoned write leaves no temporary;
// an output path that cannot be written is an error before any computation. Issues 26 and 29: a
// read-only target is refused, a symbolic link written through; SIGTERM leaves no temporary, and
// the next write removes one a SIGKILL left, never one of a live writer; a table larger than the
// free space is refused before writing.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <utime.h>

#include "report/atomic_output.hpp"

namespace mechgen::report {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

size_t entries(const fs::path& folder) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++n;
  return n;
}

class AtomicOutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("mechgen_atomic_" + std::to_string(getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
    path_ = folder_ / "result.csv";
    std::ofstream(path_) << "previous,good\n1,2\n";
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_, path_;
};

TEST_F(AtomicOutputTest, KilledWriterLeavesThePreviousFile) {
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    AtomicOutput output(path_.string());
    for (int i = 0; i < 100000; ++i) output.stream() << "0.123456789012345,";
    output.stream().flush();
    raise(SIGKILL);  // as kill -9 mid-write: no commit, no destructor
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(text_of(path_), "previous,good\n1,2\n");
  // The killed writer's temporary stays (nothing can remove it), hidden beside the file.
  EXPECT_EQ(entries(folder_), 2u);
}

TEST_F(AtomicOutputTest, CommitReplacesAndLeavesNoTemporary) {
  write_file_atomically(path_.string(), "new\n");
  EXPECT_EQ(text_of(path_), "new\n");
  EXPECT_EQ(entries(folder_), 1u);
  EXPECT_EQ(fs::status(path_).permissions() & fs::perms::others_read, fs::perms::others_read);
  {
    AtomicOutput abandoned(path_.string());  // e.g. an exception while writing
    abandoned.stream() << "half";
  }
  EXPECT_EQ(text_of(path_), "new\n");
  EXPECT_EQ(entries(folder_), 1u);
}

TEST_F(AtomicOutputTest, BadPathsAreErrorsUpFront) {
  EXPECT_THROW(check_output_path((folder_ / "missing" / "x.csv").string()), std::runtime_error);
  EXPECT_THROW(check_output_path(folder_.string()), std::runtime_error);
  EXPECT_NO_THROW(check_output_path(path_.string()));
  EXPECT_NO_THROW(write_file_atomically("/dev/null", "discarded"));  // a device: in place
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

// The hidden temporaries in `folder`.
std::vector<std::string> temporaries(const fs::path& folder) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.path().filename().string().rfind(".", 0) == 0)
      found.push_back(entry.path().filename().string());
  return found;
}

void make_old(const fs::path& path) {
  const struct utimbuf old { 1000000000, 1000000000 };  // 2001
  ASSERT_EQ(utime(path.c_str(), &old), 0);
}

TEST_F(AtomicOutputTest, ReadOnlyTargetIsRefused) {
  fs::permissions(path_, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  try {
    write_file_atomically(path_.string(), "new\n");
    FAIL() << "a read-only file was replaced";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("is read-only (mode 0444)"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(check_output_path(path_.string()), std::runtime_error);
  EXPECT_EQ(text_of(path_), "previous,good\n1,2\n");
  EXPECT_EQ(entries(folder_), 1u);
}

TEST_F(AtomicOutputTest, SymbolicLinkIsWrittenThroughInTheTargetsFolder) {
  fs::create_directories(folder_ / "real");
  fs::rename(path_, folder_ / "real" / "table.csv");
  fs::permissions(folder_ / "real" / "table.csv", fs::perms(0640));
  fs::create_symlink("real/table.csv", path_);
  write_file_atomically(path_.string(), "through\n");
  EXPECT_TRUE(fs::is_symlink(path_));
  EXPECT_EQ(text_of(folder_ / "real" / "table.csv"), "through\n");
  EXPECT_EQ(fs::status(folder_ / "real" / "table.csv").permissions(), fs::perms(0640));
  EXPECT_EQ(entries(folder_), 2u);  // the link and the folder
  EXPECT_EQ(entries(folder_ / "real"), 1u);
  // A dangling link creates its target, as a shell redirection does.
  fs::create_symlink("real/new.csv", folder_ / "dangling.csv");
  write_file_atomically((folder_ / "dangling.csv").string(), "created\n");
  EXPECT_EQ(text_of(folder_ / "real" / "new.csv"), "created\n");
}

TEST_F(AtomicOutputTest, TerminatedWriterLeavesNoTemporary) {
  for (const int signal : {SIGTERM, SIGINT}) {
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      AtomicOutput output(path_.string());
      output.stream() << "half";
      output.stream().flush();
      raise(signal);  // as kill -TERM or Ctrl-C mid-write
      _exit(0);
    }
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status));
    EXPECT_EQ(WTERMSIG(status), signal);  // still dies of the signal
    EXPECT_EQ(text_of(path_), "previous,good\n1,2\n");
    EXPECT_EQ(temporaries(folder_), std::vector<std::string>{});
  }
}

TEST_F(AtomicOutputTest, NextWriteRemovesAKilledWritersTemporaryButNotALiveOnes) {
  int ready[2], go[2];
  ASSERT_EQ(pipe(ready), 0);
  ASSERT_EQ(pipe(go), 0);
  const pid_t killed = fork();
  ASSERT_GE(killed, 0);
  if (killed == 0) {
    AtomicOutput output(path_.string());
    output.stream() << "killed";
    output.stream().flush();
    raise(SIGKILL);
  }
  int status = 0;
  ASSERT_EQ(waitpid(killed, &status, 0), killed);
  const std::vector<std::string> left = temporaries(folder_);
  ASSERT_EQ(left.size(), 1u);
  // A live writer: its temporary is as old, but it holds its lock.
  const pid_t live = fork();
  ASSERT_GE(live, 0);
  if (live == 0) {
    AtomicOutput output(path_.string());
    output.stream() << "live";
    output.stream().flush();
    char byte = 0;
    [[maybe_unused]] const ssize_t told = write(ready[1], &byte, 1);
    [[maybe_unused]] const ssize_t heard = read(go[0], &byte, 1);
    output.commit();
    _exit(0);
  }
  char byte = 0;
  ASSERT_EQ(read(ready[0], &byte, 1), 1);
  std::vector<std::string> both = temporaries(folder_);
  ASSERT_EQ(both.size(), 2u);
  for (const std::string& name : both) make_old(folder_ / name);
  write_file_atomically(path_.string(), "next\n");
  std::vector<std::string> after = temporaries(folder_);
  ASSERT_EQ(after.size(), 1u);
  EXPECT_NE(after.front(), left.front());  // the killed one went, the live one stayed
  ASSERT_EQ(write(go[1], &byte, 1), 1);
  ASSERT_EQ(waitpid(live, &status, 0), live);
  EXPECT_EQ(text_of(path_), "live");
  EXPECT_EQ(temporaries(folder_), std::vector<std::string>{});
}

TEST_F(AtomicOutputTest, TableLargerThanTheFreeSpaceIsRefusedBeforeWriting) {
  const std::uint64_t exabyte = 1000000000000000000ull;
  try {
    AtomicOutput output(path_.string(), exabyte);
    FAIL() << "an exabyte fits?";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("it needs about 1 EB and only "), std::string::npos) << message;
    EXPECT_NE(message.find(" are free in '"), std::string::npos) << message;
  }
  EXPECT_EQ(entries(folder_), 1u);
  EXPECT_NO_THROW(AtomicOutput(path_.string(), 1000));
}

}  // namespace
}  // namespace mechgen::report
