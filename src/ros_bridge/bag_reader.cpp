#include "ros_bridge/bag_reader.h"

#include <algorithm>
#include <cmath>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_msgs/TFMessage.h>

#include "ros_bridge/conversions.h"
#include "ros_bridge/topics.h"

namespace icgm::ros_bridge {

BagReader::BagReader(const std::string& path)
    : bag_(std::make_unique<rosbag::Bag>()), path_(path) {
  try {
    bag_->open(path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw LoadError("cannot read bag '" + path + "': " + e.what() +
                    " (missing, not a bag, truncated or unindexed; try 'rosbag reindex')");
  }
  try {
    rosbag::View all(*bag_);
    std::map<std::string, TopicInfo> by_name;
    for (const rosbag::ConnectionInfo* c : all.getConnections()) {
      TopicInfo& t = by_name[c->topic];
      t.name = c->topic;
      t.datatype = c->datatype;
    }
    for (auto& [name, info] : by_name) {
      rosbag::View v(*bag_, rosbag::TopicQuery(name));
      info.message_count = v.size();
      if (info.message_count > 0) {
        info.first_stamp = FromRos(v.getBeginTime());
        info.last_stamp = FromRos(v.getEndTime());
      }
      topics_.push_back(info);
    }
  } catch (const rosbag::BagException& e) {
    throw LoadError("bag '" + path + "' is corrupt: " + e.what());
  }
}

BagReader::~BagReader() = default;

const TopicInfo* BagReader::FindTopic(const std::string& name) const {
  for (const auto& t : topics_) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

struct RgbdBagStream::Pending {
  rosbag::View::iterator it;
  std::deque<sensor_msgs::Image::ConstPtr> rgb;
  std::deque<sensor_msgs::Image::ConstPtr> depth;
  std::deque<sensor_msgs::Image::ConstPtr> mask;
  bool has_mask = false;
  bool at_end = false;
};

namespace {

std::string Describe(const BagReader& r) {
  std::string s;
  for (const auto& t : r.Topics()) s += (s.empty() ? "" : ", ") + t.name;
  return s.empty() ? "no topics" : s;
}

Time Stamp(const sensor_msgs::Image& m) { return FromRos(m.header.stamp); }

}  // namespace

RgbdBagStream::RgbdBagStream(const BagReader& reader, const RgbdBagTopics& topics)
    : topics_(topics), pending_(std::make_unique<Pending>()) {
  if (topics_.depth.empty()) {
    topics_.depth =
        reader.FindTopic(topics::kDepthImageMm) ? topics::kDepthImageMm : topics::kDepthImageM;
  }
  const TopicInfo* rgb = reader.FindTopic(topics_.rgb);
  if (!rgb || rgb->message_count == 0) {
    throw LoadError("bag '" + reader.path() + "' has no RGB topic '" + topics_.rgb +
                    "' (it has: " + Describe(reader) + ")");
  }
  if (!reader.FindTopic(topics_.depth)) {
    throw LoadError("bag '" + reader.path() + "' has no depth topic '" + topics_.depth +
                    "' (it has: " + Describe(reader) + ")");
  }
  expected_frames_ = rgb->message_count;

  // First pass over the small messages.
  bool have_info = false;
  try {
    rosbag::View small(reader.bag(),
                       rosbag::TopicQuery({topics_.camera_info, topics::kTfStatic,
                                           topics_.wheel_odometry, topics_.ground_truth}));
    for (const rosbag::MessageInstance& m : small) {
      if (!have_info && m.getTopic() == topics_.camera_info) {
        if (auto info = m.instantiate<sensor_msgs::CameraInfo>()) {
          Status s = FromCameraInfo(*info, topics_.depth_scale_16u, &intrinsics_);
          if (!s.ok()) throw LoadError("bag '" + reader.path() + "': " + s.reason());
          have_info = true;
        }
      } else if (m.getTopic() == topics::kTfStatic) {
        if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) {
          for (const auto& t : tf->transforms) {
            if (t.header.frame_id == topics::kBaseFrame && t.child_frame_id == topics::kCameraFrame)
              base_to_camera_ = FromTransformMsg(t.transform);
          }
        }
      } else if (m.getTopic() == topics_.wheel_odometry) {
        if (auto o = m.instantiate<nav_msgs::Odometry>()) {
          wheel_odometry_.push_back({FromRos(o->header.stamp), FromPoseMsg(o->pose.pose)});
        }
      } else if (m.getTopic() == topics_.ground_truth) {
        if (auto p = m.instantiate<geometry_msgs::PoseStamped>()) {
          ground_truth_.push_back({FromRos(p->header.stamp), FromPoseMsg(p->pose)});
        }
      }
    }
  } catch (const rosbag::BagException& e) {
    throw LoadError("bag '" + reader.path() + "' is corrupt: " + e.what());
  }
  if (!have_info) {
    if (!topics_.fallback_intrinsics) {
      throw LoadError("bag '" + reader.path() + "' has no camera_info on '" +
                      topics_.camera_info + "'; give the camera intrinsics in the config");
    }
    intrinsics_ = *topics_.fallback_intrinsics;
  }
  auto by_stamp = [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; };
  std::stable_sort(wheel_odometry_.begin(), wheel_odometry_.end(), by_stamp);
  std::stable_sort(ground_truth_.begin(), ground_truth_.end(), by_stamp);

  std::vector<std::string> stream_topics = {topics_.rgb, topics_.depth};
  if (reader.FindTopic(topics_.dynamic_mask)) {
    stream_topics.push_back(topics_.dynamic_mask);
    pending_->has_mask = true;
  }
  view_ = std::make_unique<rosbag::View>(reader.bag(), rosbag::TopicQuery(stream_topics));
  pending_->it = view_->begin();
}

RgbdBagStream::~RgbdBagStream() = default;

bool RgbdBagStream::Emit(RgbdBagFrame* frame) {
  auto& p = *pending_;
  while (!p.rgb.empty() && !p.depth.empty()) {
    const auto rgb = p.rgb.front();
    const auto depth = p.depth.front();
    const double dt = DurationSeconds(Stamp(*depth), Stamp(*rgb));
    if (std::abs(dt) > topics_.max_sync_dt_s) {
      // Drop whichever is older; its partner is not coming.
      if (dt > 0) {
        p.rgb.pop_front();
        Drop("rgb without depth");
      } else {
        p.depth.pop_front();
        Drop("depth without rgb");
      }
      continue;
    }
    p.rgb.pop_front();
    p.depth.pop_front();
    const Time stamp = Stamp(*rgb);
    if (last_emitted_ && stamp <= *last_emitted_) {
      Drop("time went backwards");
      continue;
    }
    RgbdBagFrame f;
    f.stamp = stamp;
    f.depth_stamp = Stamp(*depth);
    if (Status s = ColorFromImageMsg(*rgb, &f.bgr); !s.ok()) {
      Drop(s.reason());
      continue;
    }
    if (Status s = DepthFromImageMsg(*depth, topics_.depth_scale_16u, &f.depth_m); !s.ok()) {
      Drop(s.reason());
      continue;
    }
    if (f.depth_m.size() != f.bgr.size()) {
      Drop("depth size differs from rgb size");
      continue;
    }
    while (!p.mask.empty() && Stamp(*p.mask.front()) < stamp) p.mask.pop_front();
    if (!p.mask.empty() && Stamp(*p.mask.front()) == stamp) {
      MonoFromImageMsg(*p.mask.front(), &f.dynamic_mask);
      p.mask.pop_front();
    }
    last_emitted_ = stamp;
    *frame = std::move(f);
    return true;
  }
  return false;
}

bool RgbdBagStream::Next(RgbdBagFrame* frame) {
  auto& p = *pending_;
  try {
    while (true) {
      // With ground-truth masks in the bag, read on until the mask of the next frame is in,
      // whatever order the recorder wrote them in.
      const bool mask_ready = !p.has_mask || p.at_end ||
                              (!p.rgb.empty() && !p.mask.empty() &&
                               Stamp(*p.mask.back()) >= Stamp(*p.rgb.front()));
      if (!p.rgb.empty() && !p.depth.empty() && mask_ready && Emit(frame)) return true;
      if (p.at_end || !status_.ok()) return false;
      if (p.it == view_->end()) {
        p.at_end = true;
        continue;
      }
      const rosbag::MessageInstance& m = *p.it;
      auto img = m.instantiate<sensor_msgs::Image>();
      if (!img) {
        Drop("not a sensor_msgs/Image on " + m.getTopic());
      } else if (m.getTopic() == topics_.rgb) {
        p.rgb.push_back(img);
      } else if (m.getTopic() == topics_.depth) {
        p.depth.push_back(img);
      } else {
        p.mask.push_back(img);
        if (p.mask.size() > 8) p.mask.pop_front();
      }
      ++p.it;
    }
  } catch (const std::exception& e) {
    status_ = Status::Error(std::string("bag read stopped: ") + e.what());
    return false;
  }
}

}  // namespace icgm::ros_bridge
