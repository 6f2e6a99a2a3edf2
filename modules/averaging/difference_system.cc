#include "averaging/difference_system.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>

#include "averaging/connectivity.h"

namespace pgba {

bool SolveDifferenceSystem(int num_nodes, const std::vector<DifferenceEdge>& edges, const Eigen::MatrixXd& b,
                           int gauge, Eigen::MatrixXd* x) {
  if (num_nodes <= 0 || gauge < 0 || gauge >= num_nodes || b.rows() != static_cast<int>(edges.size())) return false;
  const int k = static_cast<int>(b.cols());
  if (num_nodes == 1) {
    *x = Eigen::MatrixXd::Zero(1, k);
    return true;
  }
  double w_max = 0.0;
  for (const DifferenceEdge& e : edges) w_max = std::max(w_max, e.weight);
  if (!(w_max > 0.0)) return false;
  const double w_floor = 1e-12 * w_max;

  // Singular unless every node is connected to the gauge.
  UnionFind uf(num_nodes);
  for (const DifferenceEdge& e : edges) {
    if (e.i < 0 || e.j < 0 || e.i >= num_nodes || e.j >= num_nodes) return false;
    uf.Union(e.i, e.j);
  }
  for (int n = 0; n < num_nodes; ++n)
    if (uf.Find(n) != uf.Find(gauge)) return false;

  // Reduced unknowns: every node but the gauge.
  auto index = [gauge](int n) { return n < gauge ? n : n - 1; };
  const int m = num_nodes - 1;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(4 * edges.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, k);
  for (size_t e = 0; e < edges.size(); ++e) {
    const DifferenceEdge& d = edges[e];
    if (d.i == d.j) continue;
    const double w = std::max(d.weight, w_floor);
    // Row of A: +1 at j, -1 at i. Normal equations A^T W A x = A^T W b.
    if (d.i != gauge) {
      entries.emplace_back(index(d.i), index(d.i), w);
      rhs.row(index(d.i)) -= w * b.row(e);
    }
    if (d.j != gauge) {
      entries.emplace_back(index(d.j), index(d.j), w);
      rhs.row(index(d.j)) += w * b.row(e);
    }
    if (d.i != gauge && d.j != gauge) {
      entries.emplace_back(index(d.i), index(d.j), -w);
      entries.emplace_back(index(d.j), index(d.i), -w);
    }
  }
  Eigen::SparseMatrix<double> L(m, m);
  L.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(L);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd y = ldlt.solve(rhs);
  if (ldlt.info() != Eigen::Success || !y.allFinite()) return false;
  x->resize(num_nodes, k);
  for (int n = 0; n < num_nodes; ++n) {
    if (n == gauge)
      x->row(n).setZero();
    else
      x->row(n) = y.row(index(n));
  }
  return true;
}

}  // namespace pgba
