#include "nodelets/sensor_calibration.h"

#include <iomanip>
#include <sstream>

#include "core/common/option_reader.h"
#include "core/dataset/camera_options.h"
#include "nodelets/nodelet_params.h"

namespace icgm::nodelets {

CameraIntrinsics ReadSensorCalibration(const ros::NodeHandle& pnh, std::string* error) {
  error->clear();
  auto refuse = [error](const std::string& why) {
    *error += (error->empty() ? "" : "; ") + why;
  };
  CameraIntrinsics calibration;
  std::string path;
  if (GetParam(pnh, "camera_config_file", &path) && !path.empty()) {
    try {
      calibration = LoadCameraIntrinsics(path);
    } catch (const LoadError& e) {
      refuse(std::string("~camera_config_file: ") + e.what());
    }
  }
  for (const char* key :
       {"depth_time_offset_s", "depth_correction", "readout_s", "first_row_offset_s"}) {
    double value = 0.0;
    if (!GetParam(pnh, key, &value)) continue;
    // Through the camera YAML's reader, so a parameter obeys the same range as the key.
    std::ostringstream yaml;
    yaml << std::setprecision(17) << '{' << key << ": " << value << '}';
    CameraIntrinsics checked = calibration;
    try {
      ReadOptions(OptionReader::FromString(yaml.str()), &checked);
      calibration = checked;
    } catch (const LoadError& e) {
      refuse(std::string("~") + key + ": " + e.what());
    }
  }
  return calibration;
}

}  // namespace icgm::nodelets
