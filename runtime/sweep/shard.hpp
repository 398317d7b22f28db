// Shards: a long run split into N parts that run anywhere (a Slurm job array, several machines)
// and are joined by `mechgen merge` into the very bytes one run would have written.
//
// Shard I of N (1 <= I <= N) holds the items [floor((I - 1) n / N), floor(I n / N)) of n (a
// sweep's samples, a grid's values). Its part file is the single run's file with a first line
// "# mechgen part I/N", its header line and only its own rows. merge_parts() checks that the parts
// are the N shards of one run (each once, the same header) and writes the header and the rows in
// shard order, copying the row text: the merged file equals the single run's byte for byte.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace mechgen {

struct Shard {
  int index = 1;  // 1-based
  int count = 1;
  bool whole() const { return count == 1; }
};

// "I/N" -> the shard; std::invalid_argument with a one-line message when malformed or I > N.
Shard parse_shard(const std::string& text);
// The items [first, second) of n that the shard holds.
std::pair<size_t, size_t> shard_range(const Shard& shard, size_t n);
// The first line of a part file, with its newline ("" for a whole run).
std::string part_line(const Shard& shard);

// Joins the parts (in any order) into `out`. Throws std::runtime_error naming the part at fault.
void merge_parts(const std::vector<std::string>& parts, const std::string& out);

}  // namespace mechgen
