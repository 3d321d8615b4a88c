// Test helper: the package's executables next to the rostest binary (devel lib folder), so a
// .test file need not be given their paths.
#pragma once

#include <string>

namespace icgm_slam::test {

// `name` in the folder of the running executable.
std::string SiblingExecutable(const std::string& name);

}  // namespace icgm_slam::test
