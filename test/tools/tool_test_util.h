// Runs the built command-line tools from tests: exit code (or the signal that ended the
// process), stdout and stderr, and a scratch folder per test.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace icgm::tools::testing {

struct ToolRun {
  int exit_code = -1;  // -1 when ended by a signal
  int signal = 0;      // the signal that ended the process (0: exited)
  std::string out, err;
};

inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Quotes one argument for /bin/sh.
inline std::string ShellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

class ToolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = std::filesystem::temp_directory_path() /
           ("icgm_tools_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    // Read-only files in the folder do not stop remove_all (the folder is writable).
    std::filesystem::remove_all(dir_, ec);
  }
  std::string Path(const std::string& name) const { return (dir_ / name).string(); }

  // Runs ICGM_TOOL_DIR/<tool> with `args` from the source folder (relative config paths work).
  ToolRun Run(const std::string& tool, const std::vector<std::string>& args) const {
    std::string cmd = "cd " + ShellQuote(ICGM_SOURCE_DIR) + " && " +
                      ShellQuote(std::string(ICGM_TOOL_DIR) + "/" + tool);
    for (const auto& a : args) cmd += " " + ShellQuote(a);
    const std::string out = Path("stdout.txt"), err = Path("stderr.txt");
    cmd += " > " + ShellQuote(out) + " 2> " + ShellQuote(err);
    const int status = std::system(cmd.c_str());
    ToolRun r;
    r.out = ReadText(out);
    r.err = ReadText(err);
    if (WIFEXITED(status)) {
      r.exit_code = WEXITSTATUS(status);
      // A shell reports a child killed by a signal as 128 + n.
      if (r.exit_code > 128 && r.exit_code < 128 + 65) {
        r.signal = r.exit_code - 128;
        r.exit_code = -1;
      }
    } else if (WIFSIGNALED(status)) {
      r.signal = WTERMSIG(status);
    }
    return r;
  }

  std::filesystem::path dir_;
};

inline std::string Describe(const ToolRun& r) {
  std::ostringstream s;
  s << "exit " << r.exit_code << ", signal " << r.signal << "\n--- stdout:\n"
    << r.out << "\n--- stderr:\n" << r.err;
  return s.str();
}

}  // namespace icgm::tools::testing
