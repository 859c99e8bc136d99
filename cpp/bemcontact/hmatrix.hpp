// Hierarchical-matrix (H-matrix) form of a body's BEM influence matrices H
// and G: a cluster tree on the functional nodes (3 unknowns per node kept
// together), standard admissibility on the bounding boxes of the nodes'
// element supports, low-rank blocks by adaptive cross approximation (ACA
// with partial pivoting and random residual checks, on [H | s G] together),
// dense near-field blocks.  Built straight from element integrals, never
// from a dense matrix.
#pragma once

#include <cstdint>
#include <vector>

#include "operators.hpp"

namespace bemcontact {

struct HParams {
  double eps = 1e-6;     // relative accuracy of each low-rank block (Frobenius)
  double eta = 1.0;      // admissibility: min(diam) <= eta * dist
  int leaf_size = 24;    // nodes per leaf cluster (at most)
  int max_rank = 0;      // 0: no cap
  int checks = 3;        // random residual rows/columns tested after ACA stops
};

struct HCluster {
  int64_t begin = 0, end = 0;  // range in the permuted node order
  int child[2] = {-1, -1};
  double lo[3], hi[3];  // bounding box of the nodes' element supports
  bool leaf() const { return child[0] < 0; }
  int64_t size() const { return end - begin; }
};

struct HBlock {
  int tau = 0, sigma = 0;  // row and column clusters
  int rank = -1;           // -1: dense
  // dense: H, G row-major (3|tau|) x (3|sigma|); low rank: U (3|tau| x k),
  // VH, VG (3|sigma| x k), all column-major by rank index (column l
  // contiguous), so block = U VH^T (resp. U VG^T).
  std::vector<double> H, G, U, VH, VG;
  int aca_checks_failed = 0;
};

class HMatrix {
 public:
  HMatrix(const MeshView& m, const double* points, int64_t n_points, double shear_modulus,
          double nu, const QuadratureParams& q, const HParams& hp, int threads);

  int64_t n_points() const { return n_; }
  // y (3N x k, row-major, original dof order) = H a + G b  (a, b: 3N x k)
  void apply(const double* a, const double* b, double* y, int64_t k, int threads) const;
  // dense entries: rows and columns are original dof indices (sizes nr, nc):
  // out_h, out_g row-major nr x nc (computed from element integrals, with
  // the rigid-body diagonal of H) -- for tests and diagnostics.
  void entries(const int64_t* rows, int64_t nr, const int64_t* cols, int64_t nc, double* out_h,
               double* out_g) const;

  const std::vector<HCluster>& clusters() const { return clusters_; }
  const std::vector<HBlock>& blocks() const { return blocks_; }
  const std::vector<int64_t>& perm() const { return perm_; }  // permuted -> original node
  int64_t stored_doubles() const;
  double build_seconds() const { return build_s_; }

 private:
  int build_cluster(int64_t begin, int64_t end, const std::vector<double>& sup_lo,
                    const std::vector<double>& sup_hi, int leaf_size);
  void build_blocks(int tau, int sigma, double eta);
  // 3 rows (node p in permuted order) of [H | G] restricted to cluster sigma's
  // columns: out is 3 x (6 |sigma|), H columns first.
  void node_rows(int64_t p, const HCluster& sigma, const std::vector<int64_t>& elems,
                 double* out) const;
  // 3 columns (node q, permuted) of H and of G over cluster tau's rows: out
  // is (3 |tau|) x 6 row-major (H comps 0..2, then G comps 0..2).
  void node_cols(int64_t q, const HCluster& tau, double* out) const;
  void fill_dense(HBlock& b) const;
  void fill_aca(HBlock& b, uint64_t seed) const;
  std::vector<int64_t> support_elements(const HCluster& c) const;

  int64_t n_ = 0;
  const double* points_ = nullptr;  // original order (kept alive by the caller only during build)
  std::vector<double> pts_;         // permuted points (N x 3)
  std::vector<Element> els_;
  Kelvin K_;
  QuadratureParams q_;
  HParams hp_;
  double mu_ = 1.0;
  std::vector<int64_t> perm_, pos_;           // permuted->original, original->permuted
  std::vector<int64_t> n2e_ptr_, n2e_;        // functional node (original) -> elements
  std::vector<HCluster> clusters_;
  std::vector<HBlock> blocks_;
  std::vector<double> diag_;  // rigid-body diagonal of H: (N x 3 x 3), permuted order
  double build_s_ = 0.0;
};

}  // namespace bemcontact
