#include "core/nav/graph_planner.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>

namespace icgm {

GraphPlanner GraphPlanner::FromMap(const HybridMap& map) {
  GraphPlanner planner;
  for (const auto& kf : map.keyframes()) planner.AddNode(kf.global_pose.translation());
  for (const auto& link : map.links()) planner.AddEdge(link.from_id, link.to_id);
  return planner;
}

int GraphPlanner::AddNode(const Eigen::Vector3d& position_m) {
  positions_.push_back(position_m);
  adjacency_.emplace_back();
  return size() - 1;
}

Status GraphPlanner::AddEdge(int a, int b, double length_m) {
  if (a < 0 || a >= size() || b < 0 || b >= size()) {
    return Status::Error("edge " + std::to_string(a) + " - " + std::to_string(b) +
                         ": node not in the graph of " + std::to_string(size()));
  }
  if (length_m < 0.0) length_m = (positions_[a] - positions_[b]).norm();
  if (!std::isfinite(length_m)) return Status::Error("edge length is not finite");
  adjacency_[a].push_back({b, length_m});
  adjacency_[b].push_back({a, length_m});
  return Status::Ok();
}

Status GraphPlanner::PlanRoute(int start, int goal, Route* route) const {
  if (start < 0 || start >= size() || goal < 0 || goal >= size()) {
    return Status::Error("no route: node " +
                         std::to_string(start < 0 || start >= size() ? start : goal) +
                         " not in the graph of " + std::to_string(size()));
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(static_cast<size_t>(size()), inf);
  std::vector<int> parent(static_cast<size_t>(size()), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  dist[start] = 0.0;
  open.push({0.0, start});
  while (!open.empty()) {
    const auto [d, node] = open.top();
    open.pop();
    if (d > dist[node]) continue;
    if (node == goal) break;
    for (const Edge& e : adjacency_[node]) {
      const double nd = d + e.length_m;
      if (nd < dist[e.to]) {
        dist[e.to] = nd;
        parent[e.to] = node;
        open.push({nd, e.to});
      }
    }
  }
  if (dist[goal] == inf) {
    return Status::Error("no route: goal " + std::to_string(goal) + " is unreachable from " +
                         std::to_string(start));
  }
  route->nodes.clear();
  for (int n = goal; n >= 0; n = parent[n]) route->nodes.push_back(n);
  std::reverse(route->nodes.begin(), route->nodes.end());
  route->length_m = dist[goal];
  return Status::Ok();
}

int GraphPlanner::NearestNode(const Eigen::Vector3d& position_m) const {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < size(); ++i) {
    const double d = (positions_[i] - position_m).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

}  // namespace icgm
