#include "nodelets/map_services.h"

namespace icgm::nodelets {
namespace {

bool Answer(const Status& s, uint8_t* success, std::string* message) {
  *success = s.ok();
  if (!s.ok()) *message = s.reason();
  return true;
}

}  // namespace

MapServices::MapServices(ros::NodeHandle& pnh, LiveMap* map, std::function<void(Done)> done)
    : map_(map), done_(std::move(done)) {
  save_ = pnh.advertiseService("save_map", &MapServices::Save, this);
  load_ = pnh.advertiseService("load_map", &MapServices::Load, this);
  mode_ = pnh.advertiseService("set_mode", &MapServices::Mode, this);
}

bool MapServices::Save(icgm_slam::SaveMap::Request& req, icgm_slam::SaveMap::Response& res) {
  const Status s = map_->Save(req.path, &res.message);
  if (s.ok() && done_) done_(Done::kSaved);
  return Answer(s, &res.success, &res.message);
}

bool MapServices::Load(icgm_slam::LoadMap::Request& req, icgm_slam::LoadMap::Response& res) {
  const Status s = map_->Load(req.path, req.merge, &res.message);
  if (s.ok() && done_) done_(Done::kLoaded);
  return Answer(s, &res.success, &res.message);
}

bool MapServices::Mode(icgm_slam::SetMapMode::Request& req,
                       icgm_slam::SetMapMode::Response& res) {
  MapMode mode;
  const bool switches = ParseMapMode(req.mode, &mode).ok() && map_->system() &&
                        map_->system()->mode() != mode;
  if (switches && done_) done_(Done::kBeforeModeSwitch);
  return Answer(map_->SetMode(req.mode, &res.message), &res.success, &res.message);
}

}  // namespace icgm::nodelets
