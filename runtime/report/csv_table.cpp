#include "report/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "report/atomic_output.hpp"
namespace mechgen::report {
namespace {

[[noreturn]] void fail(const std::string& path, int line, const std::string& message) {
  throw CsvError(path + ":" + std::to_string(line) + ": " + message);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return fields;
}

}  // namespace

int CsvTable::column(const std::string& name) const {
  for (std::size_t i = 0; i < header.size(); ++i) {
    if (header[i] == name) return static_cast<int>(i);
  }
  return -1;
}

int CsvTable::require_column(const std::string& name) const {
  const int c = column(name);
  if (c >= 0) return c;
  std::string names;
  for (std::size_t i = 0; i < header.size() && i < 12; ++i) names += (i ? ", " : "") + header[i];
  if (header.size() > 12) names += ", ... (" + std::to_string(header.size()) + " in all)";
  throw CsvError(path + ": no column '" + name + "' (columns: " + names + ")");
}

std::vector<double> CsvTable::values(int column) const {
  std::vector<double> v;
  v.reserve(rows.size());
  for (const auto& row : rows) v.push_back(row.at(static_cast<std::size_t>(column)));
  return v;
}

CsvTable parse_csv(const std::string& text, const std::string& path, Cells cells) {
  CsvTable table;
  table.path = path;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    std::vector<std::string> fields = split_fields(line);
    if (!have_header) {
      for (std::size_t i = 0; i < fields.size(); ++i) {
        if (fields[i].empty())
          fail(path, line_no, "empty name for column " + std::to_string(i + 1));
        if (fields[i].find('"') != std::string::npos) {
          fail(path, line_no, "quoted column names are not supported: " + fields[i]);
        }
        for (std::size_t j = 0; j < i; ++j) {
          if (fields[j] == fields[i])
            fail(path, line_no, "column '" + fields[i] + "' appears twice");
        }
      }
      table.header = std::move(fields);
      have_header = true;
      continue;
    }
    if (fields.size() != table.header.size()) {
      fail(path, line_no,
           "expected " + std::to_string(table.header.size()) + " values, found " +
               std::to_string(fields.size()));
    }
    std::vector<double> row(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string& f = fields[i];
      const char* first = f.data();
      if (!f.empty() && f[0] == '+') ++first;  // from_chars takes no leading '+'
      const char* last = f.data() + f.size();
      const auto [end, ec] = std::from_chars(first, last, row[i]);
      if (f.empty() || ec == std::errc::invalid_argument || end != last) {
        fail(path, line_no, "column '" + table.header[i] + "': '" + f + "' is not a number");
      }
      if (ec == std::errc::result_out_of_range) {
        fail(path, line_no, "column '" + table.header[i] + "': '" + f + "' is out of range");
      }
      if (cells == Cells::finite && !std::isfinite(row[i]))
        fail(path, line_no, "column '" + table.header[i] + "': '" + f + "' is not finite");
    }
    table.rows.push_back(std::move(row));
  }
  if (!have_header) fail(path, line_no > 0 ? line_no : 1, "no header row (the file is empty)");
  return table;
}

CsvTable read_csv(const std::string& path, Cells cells) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ":0: cannot open for reading");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw CsvError(path + ":0: read error");
  return parse_csv(text.str(), path, cells);
}

void write_csv(const CsvTable& table, const std::string& path) {
  AtomicOutput output(path);  // throws std::runtime_error "cannot write 'PATH': ..."
  std::ostream& out = output.stream();
  for (std::size_t i = 0; i < table.header.size(); ++i) out << (i ? "," : "") << table.header[i];
  out << '\n';
  char buf[32];
  for (const auto& row : table.rows) {
    for (std::size_t i = 0; i < row.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g", row[i]);
      out << (i ? "," : "") << buf;
    }
    out << '\n';
  }
  output.commit();
}

}  // namespace mechgen::report
