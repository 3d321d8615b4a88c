#include "core/dataset/text_table.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/common/status.h"

namespace icgm {

std::vector<TextRow> ReadTextTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LoadError("cannot open '" + path + "'");
  std::vector<TextRow> rows;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // files written on Windows
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    TextRow row;
    row.line_number = line_number;
    std::istringstream fields(line);
    std::string f;
    while (fields >> f) row.fields.push_back(f);
    rows.push_back(std::move(row));
  }
  if (in.bad()) throw LoadError("error while reading '" + path + "'");
  return rows;
}

bool ParseFiniteDouble(const std::string& text, double* out) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

}  // namespace icgm
