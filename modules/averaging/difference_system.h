// Weighted least squares on a graph of difference observations x_j - x_i ~ b_e.
//
// Every linearised problem of the averaging stage has this form: the rotation increments of
// IRLS rotation averaging (three independent components), the log-scales of the triplets
// and the camera centres of translation averaging. Its normal matrix is the weighted graph
// Laplacian (times the identity for vector unknowns), so one sparse scalar factorisation
// serves all components: this is why the solvers below work per component instead of
// assembling a 3n x 3n system.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace pgba {

// One observation x_j - x_i ~ b (a row of the right-hand side matrix), with weight w > 0.
struct DifferenceEdge {
  int i = 0;
  int j = 0;
  double weight = 1.0;
};

// Solves min_x sum_e w_e || x_{j_e} - x_{i_e} - b_e ||^2 with x_gauge = 0, for `num_nodes`
// nodes and b (one row per edge, any number of columns). Returns false (x untouched) if the
// graph restricted to positive weights does not connect every node to the gauge, i.e. the
// system is singular. Weights are floored at 1e-12 of the largest one so that edges an
// IRLS step drove to (numerically) zero weight keep the Laplacian non-singular.
bool SolveDifferenceSystem(int num_nodes, const std::vector<DifferenceEdge>& edges, const Eigen::MatrixXd& b,
                           int gauge, Eigen::MatrixXd* x);

}  // namespace pgba
