// Whitespace-separated text tables as used by the TUM RGB-D benchmark files (rgb.txt,
// depth.txt, groundtruth.txt): one record per line, '#' starts a comment line, blank lines are
// skipped. Keeps line numbers so parse errors can point at the offending line.
#pragma once

#include <string>
#include <vector>

namespace icgm {

struct TextRow {
  int line_number = 0;  // 1-based line in the file
  std::vector<std::string> fields;
};

// Reads every non-comment, non-blank line of `path`; throws LoadError when the file cannot
// be opened or read.
std::vector<TextRow> ReadTextTable(const std::string& path);

// Parses a whole field as a finite double; false on trailing garbage, inf or NaN.
bool ParseFiniteDouble(const std::string& text, double* out);

}  // namespace icgm
