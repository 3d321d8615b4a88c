#include "process_cpu.h"

#include <unistd.h>

#include <dirent.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <xmlrpcpp/XmlRpcClient.h>

namespace icgm_slam::test {
namespace {

// utime + stime of a /proc stat file, ms; -1 when unreadable.
double StatCpuMs(const std::string& stat_path) {
  std::ifstream in(stat_path);
  std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t paren = stat.rfind(')');
  if (paren == std::string::npos) return -1;
  std::istringstream fields(stat.substr(paren + 2));
  std::string skip;
  for (int i = 3; i < 14; ++i) fields >> skip;
  long utime = 0, stime = 0;
  fields >> utime >> stime;
  return 1e3 * static_cast<double>(utime + stime) / sysconf(_SC_CLK_TCK);
}

}  // namespace

int NodePid(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return -1;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(static_cast<std::string>(result[2]), host, port)) return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue pid_args, pid_result;
  pid_args[0] = ros::this_node::getName();
  if (!client.execute("getPid", pid_args, pid_result) || pid_result.size() < 3) return -1;
  return static_cast<int>(pid_result[2]);
}

double ProcessCpuMs(int pid) { return StatCpuMs("/proc/" + std::to_string(pid) + "/stat"); }

double ProcessCpuMsWithout(int pid, const std::string& excluded_thread) {
  const std::string task_dir = "/proc/" + std::to_string(pid) + "/task";
  DIR* dir = opendir(task_dir.c_str());
  if (dir == nullptr) return -1;
  double total = 0.0;
  while (const dirent* entry = readdir(dir)) {
    const std::string tid = entry->d_name;
    if (tid == "." || tid == "..") continue;
    std::string name;
    std::getline(std::ifstream(task_dir + "/" + tid + "/comm"), name);
    if (name == excluded_thread) continue;
    const double ms = StatCpuMs(task_dir + "/" + tid + "/stat");
    if (ms > 0) total += ms;
  }
  closedir(dir);
  return total;
}

}  // namespace icgm_slam::test
