// Test helper: CPU time of another ROS node's process, read from /proc, for benchmarks that
// compare a nodelet manager with the offline tools.
#pragma once

#include <string>

namespace icgm_slam::test {

// The pid of a node of this master (XML-RPC getPid), or -1.
int NodePid(const std::string& node);

// User + system CPU time of a process, ms (/proc/<pid>/stat fields 14 and 15); -1 when unreadable.
double ProcessCpuMs(int pid);

// The same summed over the process's threads, leaving out those named `excluded_thread`
// (/proc/<pid>/task/*/comm): e.g. a virtual camera's decoding, which a real camera does in its
// hardware. Threads that ended before the call are not counted (sample at start and end of a
// run while the process's threads live). -1 when unreadable.
double ProcessCpuMsWithout(int pid, const std::string& excluded_thread);

}  // namespace icgm_slam::test
