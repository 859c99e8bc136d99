// Cluster tree on the functional nodes of a body for the H-matrix (hmatrix.hpp):
// median splits of the nodes' points along their longest axis (3 unknowns per
// node kept together), and per cluster the bounding box of its nodes' element
// supports, which the admissibility of a block compares.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace bemcontact {

struct HCluster {
  int64_t begin = 0, end = 0;  // range in the permuted node order
  int child[2] = {-1, -1};
  double lo[3], hi[3];  // bounding box of the nodes' element supports
  bool leaf() const { return child[0] < 0; }
  int64_t size() const { return end - begin; }
};

// Box diameter, distance between two boxes (0 when they overlap) and between
// their centres.
inline double box_diam(const HCluster& c) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) s += (c.hi[d] - c.lo[d]) * (c.hi[d] - c.lo[d]);
  return std::sqrt(s);
}

inline double box_dist(const HCluster& a, const HCluster& b) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double g = std::max({0.0, a.lo[d] - b.hi[d], b.lo[d] - a.hi[d]});
    s += g * g;
  }
  return std::sqrt(s);
}

inline double center_dist(const HCluster& a, const HCluster& b) {
  double s = 0.0;
  for (int d = 0; d < 3; ++d) {
    const double g = 0.5 * (a.lo[d] + a.hi[d] - b.lo[d] - b.hi[d]);
    s += g * g;
  }
  return std::sqrt(s);
}

// The cluster tree of the nodes 0 .. n-1 (points: n x 3; sup_lo, sup_hi: n x 3,
// each node's support box), leaves of at most leaf_size nodes: clusters[0] is
// the root, perm maps the permuted node order (clusters are ranges of it) to
// the original one.
void build_cluster_tree(const double* points, int64_t n, const std::vector<double>& sup_lo,
                        const std::vector<double>& sup_hi, int leaf_size,
                        std::vector<HCluster>& clusters, std::vector<int64_t>& perm);

}  // namespace bemcontact
