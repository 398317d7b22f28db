// Shards: parsing I/N, the ranges they hold (every item once, in order), and merging parts.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "sweep/shard.hpp"

namespace mechgen {
namespace {

namespace fs = std::filesystem;

TEST(Shard, ParsesIOverN) {
  const Shard shard = parse_shard("2/5");
  EXPECT_EQ(shard.index, 2);
  EXPECT_EQ(shard.count, 5);
  for (const char* bad : {"0/3", "4/3", "1/0", "1", "a/2", "1/2x", "/2", "-1/2"})
    EXPECT_THROW(parse_shard(bad), std::invalid_argument) << bad;
}

TEST(Shard, RangesCoverEveryItemOnceInOrder) {
  // 10 items in 4 shards: floor(10 i / 4) = 0, 2, 5, 7, 10.
  const std::pair<size_t, size_t> expected[] = {{0, 2}, {2, 5}, {5, 7}, {7, 10}};
  for (int i = 1; i <= 4; ++i) EXPECT_EQ(shard_range({i, 4}, 10), expected[i - 1]) << i;
  EXPECT_EQ(shard_range({1, 1}, 7), (std::pair<size_t, size_t>{0, 7}));
  EXPECT_EQ(shard_range({1, 3}, 2), (std::pair<size_t, size_t>{0, 0}));  // more shards than items
  EXPECT_EQ(part_line({3, 4}), "# mechgen part 3/4\n");
  EXPECT_EQ(part_line({1, 1}), "");
}

class MergeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("mechgen_shard_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return (dir_ / name).string();
  }
  std::string read(const std::string& name) {
    std::ifstream in(dir_ / name, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  fs::path dir_;
};

TEST_F(MergeTest, JoinsPartsInShardOrder) {
  const std::string a = write("a.csv", "# mechgen part 1/3\nt,x\n0,1\n1,2\n");
  const std::string b = write("b.csv", "# mechgen part 2/3\nt,x\n");  // an empty shard
  const std::string c = write("c.csv", "# mechgen part 3/3\nt,x\n2,3.5\n");
  merge_parts({c, a, b}, (dir_ / "all.csv").string());
  EXPECT_EQ(read("all.csv"), "t,x\n0,1\n1,2\n2,3.5\n");
}

TEST_F(MergeTest, RefusesIncompleteOrMixedParts) {
  const std::string a = write("a.csv", "# mechgen part 1/2\nt,x\n0,1\n");
  const std::string b = write("b.csv", "# mechgen part 2/2\nt,y\n1,2\n");
  const std::string c = write("c.csv", "# mechgen part 2/3\nt,x\n1,2\n");
  const std::string plain = write("plain.csv", "t,x\n0,1\n");
  const std::string out = (dir_ / "out.csv").string();
  const auto message = [&](const std::vector<std::string>& parts) {
    try {
      merge_parts(parts, out);
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({a}), "part 2/2 is missing");
  EXPECT_EQ(message({a, a}), a + ": part 1 given twice");
  EXPECT_EQ(message({a, b}), b + ": its columns are not those of the other parts");
  EXPECT_EQ(message({a, c}), c + ": part 2 of 3, the other parts are of 2");
  EXPECT_EQ(message({plain}),
            plain + ": not a part written with --shard I/N (its first line is 't,x')");
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace mechgen
