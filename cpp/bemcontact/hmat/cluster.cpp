// Cluster tree (see cluster.hpp).
#include "hmat/cluster.hpp"

#include <numeric>

namespace bemcontact {

namespace {

// Cluster of the nodes perm[begin .. end), its subtree appended to clusters.
int build_cluster(std::vector<HCluster>& clusters, std::vector<int64_t>& perm,
                  const double* points, int64_t begin, int64_t end,
                  const std::vector<double>& sup_lo, const std::vector<double>& sup_hi,
                  int leaf_size) {
  const int id = static_cast<int>(clusters.size());
  clusters.emplace_back();
  HCluster c;
  c.begin = begin;
  c.end = end;
  double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (int d = 0; d < 3; ++d) {
    c.lo[d] = INFINITY;
    c.hi[d] = -INFINITY;
  }
  for (int64_t p = begin; p < end; ++p) {
    const int64_t i = perm[p];
    for (int d = 0; d < 3; ++d) {
      c.lo[d] = std::min(c.lo[d], sup_lo[3 * i + d]);
      c.hi[d] = std::max(c.hi[d], sup_hi[3 * i + d]);
      plo[d] = std::min(plo[d], points[3 * i + d]);
      phi[d] = std::max(phi[d], points[3 * i + d]);
    }
  }
  if (end - begin > leaf_size) {
    int axis = 0;
    for (int d = 1; d < 3; ++d)
      if (phi[d] - plo[d] > phi[axis] - plo[axis]) axis = d;
    const int64_t mid = begin + (end - begin) / 2;
    std::nth_element(perm.begin() + begin, perm.begin() + mid, perm.begin() + end,
                     [points, axis](int64_t a, int64_t b) {
                       const double xa = points[3 * a + axis], xb = points[3 * b + axis];
                       return xa < xb || (xa == xb && a < b);
                     });
    const int c0 = build_cluster(clusters, perm, points, begin, mid, sup_lo, sup_hi, leaf_size);
    const int c1 = build_cluster(clusters, perm, points, mid, end, sup_lo, sup_hi, leaf_size);
    c.child[0] = c0;
    c.child[1] = c1;
  }
  clusters[id] = c;
  return id;
}

}  // namespace

void build_cluster_tree(const double* points, int64_t n, const std::vector<double>& sup_lo,
                        const std::vector<double>& sup_hi, int leaf_size,
                        std::vector<HCluster>& clusters, std::vector<int64_t>& perm) {
  perm.resize(n);
  std::iota(perm.begin(), perm.end(), 0);
  clusters.reserve(4 * (n / leaf_size + 1));
  build_cluster(clusters, perm, points, 0, n, sup_lo, sup_hi, leaf_size);
}

}  // namespace bemcontact
