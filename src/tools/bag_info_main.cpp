// icgm_bag_info: what a rosbag holds: topics, message types, counts, rates and time span.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "core/common/status.h"
#include "ros_bridge/bag_reader.h"
#include "tools/cli_args.h"

namespace {

constexpr char kUsage[] = "usage: icgm_bag_info FILE.bag\n";
constexpr icgm::tools::ToolInfo kTool{"icgm_bag_info", kUsage};

int UsageError(const std::string& message) { return icgm::tools::UsageError(kTool, message); }

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  try {
    const icgm::tools::CliArgs args(argc, argv, {}, {});
    if (args.help()) return icgm::tools::PrintUsage(kTool);
    if (args.positional().size() != 1) return UsageError("expected exactly one bag file");
    path = args.positional().front();
  } catch (const std::invalid_argument& e) {
    return UsageError(e.what());
  }

  try {
    const icgm::ros_bridge::BagReader reader(path);
    const auto& topics = reader.Topics();
    if (topics.empty()) {
      std::printf("%s: empty bag (no messages)\n", path.c_str());
      return 0;
    }
    icgm::Time start = topics.front().first_stamp, end = topics.front().last_stamp;
    size_t total = 0, name_width = 5, type_width = 4;
    for (const auto& t : topics) {
      start = std::min(start, t.first_stamp);
      end = std::max(end, t.last_stamp);
      total += t.message_count;
      name_width = std::max(name_width, t.name.size());
      type_width = std::max(type_width, t.datatype.size());
    }
    std::printf("path      %s\n", path.c_str());
    std::printf("start     %s\nend       %s\n", start.ToString().c_str(), end.ToString().c_str());
    std::printf("duration  %.3f s\nmessages  %zu\n\n", icgm::DurationSeconds(end, start), total);
    std::printf("%-*s  %-*s  %8s  %9s\n", static_cast<int>(name_width), "topic",
                static_cast<int>(type_width), "type", "count", "rate Hz");
    for (const auto& t : topics) {
      const double span = icgm::DurationSeconds(t.last_stamp, t.first_stamp);
      char rate[32] = "-";
      if (t.message_count > 1 && span > 0.0) {
        std::snprintf(rate, sizeof(rate), "%.2f", (t.message_count - 1) / span);
      }
      std::printf("%-*s  %-*s  %8zu  %9s\n", static_cast<int>(name_width), t.name.c_str(),
                  static_cast<int>(type_width), t.datatype.c_str(), t.message_count, rate);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "icgm_bag_info: %s\n", e.what());
    return 1;
  }
}
