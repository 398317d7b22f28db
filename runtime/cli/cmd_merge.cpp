// mechgen merge: joins the parts of a sharded sweep or grid (--shard I/N) into the file one run
// would have written.
#include <iostream>
#include <string>
#include <vector>

#include "cli/command.hpp"
#include "sweep/shard.hpp"

namespace mechgen::cli {

namespace {

const char* const kMergeHelp =
    R"(usage: mechgen merge --out FILE.csv PART.csv...

Joins the parts written by `mechgen sweep ... --shard I/N --out PART.csv` (or `mechgen grid`) into
the file the unsharded run writes, byte for byte. The parts may be given in any order; each of the
N parts must be there exactly once, all of the same run (same columns).
)";

int run_merge(const Args& args) {
  if (!args.has("--out")) throw UsageError("missing --out FILE.csv");
  const std::vector<std::string>& parts = args.positionals();
  if (parts.empty()) throw UsageError("no PART.csv to merge");
  const std::string out = args.get("--out");
  merge_parts(parts, out);
  std::cout << "merge: " << parts.size() << " parts -> " << out << "\n";
  return 0;
}

}  // namespace

Command merge_command() {
  return {"merge",
          "join the parts of a sharded sweep or grid (--shard I/N) into one file",
          kMergeHelp,
          {{"--out", "-o", true}},
          &run_merge};
}

}  // namespace mechgen::cli
