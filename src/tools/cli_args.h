// Command-line conventions shared by every tool: positional arguments plus "--name value" (or
// "--name=value") options and "--flag" switches; `--help` (or `-h`) anywhere prints the usage on
// stdout and exits 0 whatever else is given; a bad argument prints "<tool>: <reason>" and the
// usage on stderr and exits 2; a failure at run time prints "<tool>: <reason>" and exits 1.
#pragma once

#include <cstddef>
#include <initializer_list>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/common/enum_names.h"

namespace icgm::tools {

// A tool's name (for messages) and usage text.
struct ToolInfo {
  const char* name;
  const char* usage;
};

// Prints the usage on stdout; returns 0 (the exit code of --help).
int PrintUsage(const ToolInfo& tool);
// Prints "<tool>: <reason>" and the usage on stderr; returns 2.
int UsageError(const ToolInfo& tool, const std::string& reason);
// Prints "<tool>: <reason>" on stderr; returns 1.
int Failure(const ToolInfo& tool, const std::string& reason);

// Why no file can be written at `path` ("cannot write 'x': folder 'd' does not exist", or is not
// writable), or "" when it can. Tools check their outputs before a long run.
std::string OutputFolderProblem(const std::string& path);
// The first problem among `paths` (empty paths, outputs not asked for, are skipped), or "".
std::string OutputFolderProblem(std::initializer_list<std::string> paths);

// "input ended early after N frames: <error>" for a run whose input failed after `frames`
// frames, or "" when `input_error` is empty (the input ended normally).
std::string InputEndedEarly(size_t frames, const std::string& input_error);

class CliArgs {
 public:
  // `value_options` take a value ("--thr 0.08"); `flags` do not ("--auto-thr"). "help" is always
  // known: with --help or -h anywhere nothing else is checked and help() is true. Throws
  // std::invalid_argument on an unknown option or a missing value.
  CliArgs(int argc, char** argv, const std::set<std::string>& value_options,
          const std::set<std::string>& flags);

  bool help() const { return help_; }

  const std::vector<std::string>& positional() const { return positional_; }
  bool Has(const std::string& name) const;
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  double GetDouble(const std::string& name, double fallback) const;
  int GetInt(const std::string& name, int fallback) const;
  // One of an enum's choices spelt as in the config files (enum_names.h); throws
  // std::invalid_argument("--detector: 'x' is not one of {orb, ...}") for any other.
  template <typename E>
  E GetEnum(const std::string& name, E fallback) const {
    if (!Has(name)) return fallback;
    const std::string text = Get(name);
    if (const auto value = ParseEnum<E>(text)) return *value;
    throw std::invalid_argument("--" + name + ": " + NotOneOf<E>(text));
  }
  // Throws std::invalid_argument("missing required option --name").
  std::string Require(const std::string& name) const;

 private:
  std::vector<std::string> positional_;
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_set_;
  bool help_ = false;
};

}  // namespace icgm::tools
