#include "tools/cli_args.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace icgm::tools {

namespace {
// The usage text with exactly one trailing newline.
std::string UsageText(const ToolInfo& tool) {
  std::string usage = tool.usage;
  while (!usage.empty() && usage.back() == '\n') usage.pop_back();
  return usage + "\n";
}
}  // namespace

int PrintUsage(const ToolInfo& tool) {
  std::fputs(UsageText(tool).c_str(), stdout);
  return 0;
}

int UsageError(const ToolInfo& tool, const std::string& reason) {
  std::fprintf(stderr, "%s: %s\n%s", tool.name, reason.c_str(), UsageText(tool).c_str());
  return 2;
}

int Failure(const ToolInfo& tool, const std::string& reason) {
  std::fprintf(stderr, "%s: %s\n", tool.name, reason.c_str());
  return 1;
}

std::string OutputFolderProblem(const std::string& path) {
  const std::string parent = std::filesystem::path(path).parent_path().string();
  const std::string folder = parent.empty() ? "." : parent;
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    return "cannot write '" + path + "': folder '" + folder + "' does not exist";
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    return "cannot write '" + path + "': folder '" + folder + "' is not writable";
  }
  return "";
}

std::string OutputFolderProblem(std::initializer_list<std::string> paths) {
  for (const std::string& path : paths) {
    const std::string problem = path.empty() ? "" : OutputFolderProblem(path);
    if (!problem.empty()) return problem;
  }
  return "";
}

std::string InputEndedEarly(size_t frames, const std::string& input_error) {
  if (input_error.empty()) return "";
  return "input ended early after " + std::to_string(frames) + " frames: " + input_error;
}

CliArgs::CliArgs(int argc, char** argv, const std::set<std::string>& value_options,
                 const std::set<std::string>& flags) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      help_ = true;
      flags_set_.insert("help");
      return;
    }
  }
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string name = a.substr(2);
      std::string inline_value;
      const bool has_inline = name.find('=') != std::string::npos;
      if (has_inline) {
        inline_value = name.substr(name.find('=') + 1);
        name = name.substr(0, name.find('='));
      }
      if (value_options.count(name)) {
        if (has_inline) {
          values_[name] = inline_value;
        } else {
          if (i + 1 >= argc) throw std::invalid_argument("option --" + name + " needs a value");
          values_[name] = argv[++i];
        }
      } else if (flags.count(name) && !has_inline) {
        flags_set_.insert(name);
      } else {
        throw std::invalid_argument("unknown option --" + name);
      }
    } else {
      positional_.push_back(a);
    }
  }
}

bool CliArgs::Has(const std::string& name) const {
  return values_.count(name) || flags_set_.count(name);
}

std::string CliArgs::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double CliArgs::GetDouble(const std::string& name, double fallback) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  try {
    size_t pos = 0;
    const double v = std::stod(it->second, &pos);
    if (pos != it->second.size()) throw std::invalid_argument("");
    return v;
  } catch (const std::exception&) {
    throw std::invalid_argument("option --" + name + ": '" + it->second + "' is not a number");
  }
}

int CliArgs::GetInt(const std::string& name, int fallback) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  try {
    size_t pos = 0;
    const int v = std::stoi(it->second, &pos);
    if (pos != it->second.size()) throw std::invalid_argument("");
    return v;
  } catch (const std::exception&) {
    throw std::invalid_argument("option --" + name + ": '" + it->second + "' is not an integer");
  }
}

std::string CliArgs::Require(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) throw std::invalid_argument("missing required option --" + name);
  return it->second;
}

}  // namespace icgm::tools
