#include "sweep/shard.hpp"

#include <charconv>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace mechgen {

namespace {

bool parse_int(const std::string& text, int& value) {
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(text.data(), end, value);
  return error == std::errc() && ptr == end && !text.empty();
}

constexpr const char* kPartPrefix = "# mechgen part ";

}  // namespace

Shard parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  Shard shard;
  if (slash == std::string::npos || !parse_int(text.substr(0, slash), shard.index) ||
      !parse_int(text.substr(slash + 1), shard.count))
    throw std::invalid_argument("expected I/N (shard I of N, 1 <= I <= N), got '" + text + "'");
  if (shard.count < 1 || shard.index < 1 || shard.index > shard.count)
    throw std::invalid_argument("shard " + text + ": I must be in 1 .. N");
  return shard;
}

std::pair<size_t, size_t> shard_range(const Shard& shard, size_t n) {
  const auto bound = [&](int i) {
    return static_cast<size_t>(static_cast<unsigned long long>(n) * static_cast<unsigned>(i) /
                               static_cast<unsigned>(shard.count));
  };
  return {bound(shard.index - 1), bound(shard.index)};
}

std::string part_line(const Shard& shard) {
  if (shard.whole()) return "";
  return kPartPrefix + std::to_string(shard.index) + "/" + std::to_string(shard.count) + "\n";
}

void merge_parts(const std::vector<std::string>& parts, const std::string& out) {
  if (parts.empty()) throw std::runtime_error("no parts to merge");
  std::string header;
  std::map<int, std::string> rows;  // shard index -> its row lines
  int count = 0;
  for (const std::string& path : parts) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot read");
    std::stringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    const size_t first = text.find('\n');
    const size_t second = first == std::string::npos ? first : text.find('\n', first + 1);
    const std::string line = text.substr(0, first);
    Shard shard;
    try {
      if (second == std::string::npos || line.rfind(kPartPrefix, 0) != 0)
        throw std::invalid_argument("");
      shard = parse_shard(line.substr(std::string(kPartPrefix).size()));
    } catch (const std::invalid_argument&) {
      throw std::runtime_error(path + ": not a part written with --shard I/N (its first line is '" +
                               line.substr(0, 60) + "')");
    }
    if (count == 0) count = shard.count;
    if (shard.count != count)
      throw std::runtime_error(path + ": part " + std::to_string(shard.index) + " of " +
                               std::to_string(shard.count) + ", the other parts are of " +
                               std::to_string(count));
    const std::string this_header = text.substr(first + 1, second - first);
    if (header.empty()) header = this_header;
    if (this_header != header)
      throw std::runtime_error(path + ": its columns are not those of the other parts");
    if (!rows.emplace(shard.index, text.substr(second + 1)).second)
      throw std::runtime_error(path + ": part " + std::to_string(shard.index) + " given twice");
  }
  for (int i = 1; i <= count; ++i)
    if (!rows.count(i))
      throw std::runtime_error("part " + std::to_string(i) + "/" + std::to_string(count) +
                               " is missing");
  std::ofstream file(out, std::ios::binary);
  file << header;
  for (const auto& [index, text] : rows) file << text;
  file.close();
  if (!file) throw std::runtime_error("cannot write '" + out + "'");
}

}  // namespace mechgen
