#include "core/sensor/virtual_device_uri.h"

#include <cstdlib>
#include <sstream>

namespace icgm {

bool IsVirtualDeviceUri(const std::string& uri) {
  return uri.rfind(kVirtualDeviceScheme, 0) == 0;
}

Status ParseVirtualDeviceUri(const std::string& uri, VirtualDeviceConfig* out) {
  const std::string where = "virtual device URI '" + uri + "': ";
  if (!IsVirtualDeviceUri(uri)) {
    return Status::Error(where + "does not start with " + kVirtualDeviceScheme);
  }
  VirtualDeviceConfig c;
  const std::string rest = uri.substr(sizeof(kVirtualDeviceScheme) - 1);
  const size_t q = rest.find('?');
  c.source = rest.substr(0, q);
  if (c.source != "tum" && c.source != "sim") {
    return Status::Error(where + "unknown source '" + c.source + "' (tum or sim)");
  }
  std::stringstream query(q == std::string::npos ? std::string() : rest.substr(q + 1));
  std::string item;
  while (std::getline(query, item, '&')) {
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    const std::string key = item.substr(0, eq);
    const std::string value = eq == std::string::npos ? std::string() : item.substr(eq + 1);
    char* end = nullptr;
    if (key == "dir" && c.source == "tum") {
      c.dir = value;
    } else if (key == "scenario" && c.source == "sim") {
      c.scenario = value;
    } else if (key == "camera" && c.source == "tum") {
      c.camera_yaml = value;
    } else if (key == "frames") {
      const long n = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end != '\0' || n < 0) {
        return Status::Error(where + "frames must be an integer >= 0");
      }
      c.max_frames = static_cast<int>(n);
    } else if (key == "rate") {
      c.rate = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(c.rate > 0.0 && c.rate <= 100.0)) {
        return Status::Error(where + "rate must be in (0, 100]");
      }
    } else if (key == "loop") {
      if (value != "0" && value != "1") return Status::Error(where + "loop must be 0 or 1");
      c.loop = value == "1";
    } else {
      return Status::Error(where + "unknown parameter '" + key + "' for the " + c.source +
                           " source");
    }
  }
  if (c.source == "tum" && c.dir.empty()) {
    return Status::Error(where + "needs dir=/path/to/tum/folder");
  }
  if (c.source == "sim" && c.scenario.empty()) {
    return Status::Error(where + "needs scenario=/path/to/scenario.yaml");
  }
  *out = c;
  return Status::Ok();
}

}  // namespace icgm
