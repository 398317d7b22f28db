// Outputs are written atomically (issue 16): a writer killed mid-write (SIGKILL, no destructor
// runs) leaves the previous file intact; a clean exit or an abandoned write leaves no temporary;
// an output path that cannot be written is an error before any computation.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

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

}  // namespace
}  // namespace mechgen::report
