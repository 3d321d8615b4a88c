#include "core/dataset/trajectory.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iomanip>

#include "core/common/status.h"
#include "core/dataset/text_table.h"

namespace icgm {

Trajectory ReadTumTrajectory(const std::string& path) {
  Trajectory out;
  for (const TextRow& row : ReadTextTable(path)) {
    const std::string where = path + ":" + std::to_string(row.line_number) + ": ";
    if (row.fields.size() != 8) {
      throw LoadError(where + "expected 8 fields 'timestamp tx ty tz qx qy qz qw', got " +
                      std::to_string(row.fields.size()));
    }
    StampedPose sp;
    if (!Time::Parse(row.fields[0], &sp.stamp)) {
      throw LoadError(where + "bad timestamp '" + row.fields[0] + "'");
    }
    double v[7];
    for (int k = 0; k < 7; ++k) {
      if (!ParseFiniteDouble(row.fields[k + 1], &v[k])) {
        throw LoadError(where + "bad number '" + row.fields[k + 1] + "'");
      }
    }
    const Quat q(v[6], v[3], v[4], v[5]);  // Eigen takes (w, x, y, z)
    if (q.norm() < 1e-9) throw LoadError(where + "zero quaternion");
    sp.pose = MakePose(Vec3(v[0], v[1], v[2]), q);
    out.push_back(sp);
  }
  return out;
}

void WriteTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw LoadError("cannot write '" + tmp + "'");
    f << "# timestamp tx ty tz qx qy qz qw\n";
    f << std::setprecision(9);
    for (const StampedPose& sp : trajectory) {
      const Quat q(sp.pose.linear());
      const Vec3 t = sp.pose.translation();
      // Sub-microsecond stamps keep all 9 decimals; TUM stamps keep their usual 6.
      const int decimals = sp.stamp.nanoseconds() % 1000 == 0 ? 6 : 9;
      f << sp.stamp.ToString(decimals) << ' ' << t.x() << ' ' << t.y() << ' ' << t.z() << ' '
        << q.x() << ' ' << q.y() << ' ' << q.z() << ' ' << q.w() << '\n';
    }
    f.flush();
    if (!f) {
      std::remove(tmp.c_str());
      throw LoadError("error while writing '" + tmp + "'");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw LoadError("cannot rename '" + tmp + "' to '" + path + "'");
  }
}

bool IsSortedByStamp(const Trajectory& trajectory) {
  return std::is_sorted(
      trajectory.begin(), trajectory.end(),
      [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
}

void SortByStamp(Trajectory* trajectory) {
  std::stable_sort(trajectory->begin(), trajectory->end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.stamp < b.stamp; });
}

std::vector<Time> Stamps(const Trajectory& trajectory) {
  std::vector<Time> out;
  out.reserve(trajectory.size());
  for (const StampedPose& sp : trajectory) out.push_back(sp.stamp);
  return out;
}

std::optional<Pose3> PoseAt(const Trajectory& trajectory, Time t, double max_gap_s) {
  // First pose with stamp >= t.
  const auto it =
      std::lower_bound(trajectory.begin(), trajectory.end(), t,
                       [](const StampedPose& sp, const Time& value) { return sp.stamp < value; });
  if (it == trajectory.end()) return std::nullopt;
  if (it->stamp == t) return it->pose;
  if (it == trajectory.begin()) return std::nullopt;
  const StampedPose& a = *(it - 1);
  const StampedPose& b = *it;
  const double gap_s = DurationSeconds(b.stamp, a.stamp);
  if (gap_s > max_gap_s) return std::nullopt;
  return Interpolate(a.pose, b.pose, DurationSeconds(t, a.stamp) / gap_s);
}

}  // namespace icgm
