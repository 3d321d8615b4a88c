// Minimal command-line parsing shared by the offline tools: positional arguments plus
// "--name value" options and "--flag" switches. Unknown options are an error with usage.
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace icgm::tools {

class CliArgs {
 public:
  // `value_options` take a value ("--thr 0.08"); `flags` do not ("--auto-thr").
  CliArgs(int argc, char** argv, const std::set<std::string>& value_options,
          const std::set<std::string>& flags);

  const std::vector<std::string>& positional() const { return positional_; }
  bool Has(const std::string& name) const;
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  double GetDouble(const std::string& name, double fallback) const;
  int GetInt(const std::string& name, int fallback) const;
  // Throws std::invalid_argument("missing required option --name").
  std::string Require(const std::string& name) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_set_;
};

}  // namespace icgm::tools
