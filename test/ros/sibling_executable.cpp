#include "sibling_executable.h"

#include <unistd.h>

namespace icgm_slam::test {

std::string SiblingExecutable(const std::string& name) {
  char self[4096] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
  std::string dir = n > 0 ? std::string(self, static_cast<size_t>(n)) : std::string();
  dir = dir.substr(0, dir.rfind('/') + 1);
  return dir + name;
}

}  // namespace icgm_slam::test
