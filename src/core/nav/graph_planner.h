// Shortest routes on the hybrid map's graph (thesis 6.1.2: the map keeps a correct topology, so
// Dijkstra's algorithm plans the route). Nodes are keyframes at the translation of their global
// pose L_n; edges are the odometry and loop-closure links, weighted by the metric distance between
// their nodes (a loop link between two views of one place costs almost nothing).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/common/status.h"
#include "core/map/hybrid_map.h"

namespace icgm {

struct Route {
  std::vector<int> nodes;  // start .. goal
  double length_m = 0.0;
};

class GraphPlanner {
 public:
  GraphPlanner() = default;
  static GraphPlanner FromMap(const HybridMap& map);

  int AddNode(const Eigen::Vector3d& position_m);
  // Undirected edge; length_m < 0 means the distance between the node positions.
  Status AddEdge(int a, int b, double length_m = -1.0);

  // Dijkstra; fails with a reason on unknown nodes or an unreachable goal.
  Status PlanRoute(int start, int goal, Route* route) const;
  // Node closest to a position (-1 on an empty graph).
  int NearestNode(const Eigen::Vector3d& position_m) const;

  int size() const { return static_cast<int>(positions_.size()); }
  const Eigen::Vector3d& position(int node) const { return positions_.at(node); }

 private:
  struct Edge {
    int to;
    double length_m;
  };
  std::vector<Eigen::Vector3d> positions_;
  std::vector<std::vector<Edge>> adjacency_;
};

}  // namespace icgm
