// Numeric CSV tables as the sweep writes them: one header row of column names, then one row of
// numbers per sample, comma separated; quoting is not supported. A cell "nan" or "inf" is an
// error unless the reader asks for Cells::any (a plot draws gaps; an analysis must not compute
// with them).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace mechgen::report {

// Every problem is one line "FILE:LINE: MESSAGE" (LINE 1-based; 0 when the file cannot be read).
class CsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct CsvTable {
  std::string path;  // where it was read from, for messages; may be empty
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;  // each as long as header

  int column(const std::string& name) const;  // index in header, -1 when absent
  // As column(), but throws CsvError "FILE: no column 'NAME' (columns: a, b, ...)" when absent.
  int require_column(const std::string& name) const;
  std::vector<double> values(int column) const;  // one column, top to bottom
};

enum class Cells { finite, any };
CsvTable read_csv(const std::string& path, Cells cells = Cells::finite);
// Parses text already in memory; `path` only labels the messages.
CsvTable parse_csv(const std::string& text, const std::string& path, Cells cells = Cells::finite);
// Writes header and rows with 17 significant digits, so read_csv() returns the same doubles.
void write_csv(const CsvTable& table, const std::string& path);

}  // namespace mechgen::report
