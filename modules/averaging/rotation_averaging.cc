#include "averaging/rotation_averaging.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>

#include "pgba/io/option_ranges.h"
#include "averaging/connectivity.h"
#include "averaging/difference_system.h"
#include "pgba/geometry/rotation.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"

namespace pgba {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The observations re-indexed on dense node numbers.
struct Graph {
  std::vector<uint32_t> ids;  // node -> image id (ascending)
  std::vector<int> i, j;      // per observation
  std::vector<Eigen::Matrix3d> R_ij;
  std::vector<double> prior, support;
  std::vector<int> source;  // -1: its own
};

Graph BuildGraph(const std::vector<RelativeRotation>& observations) {
  std::map<uint32_t, int> index;
  for (const RelativeRotation& o : observations) {
    index.emplace(o.image_id1, 0);
    index.emplace(o.image_id2, 0);
  }
  Graph g;
  for (auto& [id, n] : index) {
    n = static_cast<int>(g.ids.size());
    g.ids.push_back(id);
  }
  for (const RelativeRotation& o : observations) {
    if (o.image_id1 == o.image_id2 || !(o.weight > 0.0) || !o.R_21.allFinite()) continue;
    g.i.push_back(index[o.image_id1]);
    g.j.push_back(index[o.image_id2]);
    g.R_ij.push_back(o.R_21);
    g.prior.push_back(o.weight);
    g.support.push_back(std::max(o.support, 0.0));
    g.source.push_back(o.source);
  }
  return g;
}

// The observations e whose indices are listed, on the nodes they touch (renumbered);
// `node_of` receives the old -> new node map (-1: dropped).
Graph Subgraph(const Graph& g, const std::vector<int>& kept_edges, const std::vector<bool>& kept_nodes,
               std::vector<int>* node_of) {
  Graph s;
  node_of->assign(g.ids.size(), -1);
  for (size_t n = 0; n < g.ids.size(); ++n)
    if (kept_nodes[n]) {
      (*node_of)[n] = static_cast<int>(s.ids.size());
      s.ids.push_back(g.ids[n]);
    }
  for (int e : kept_edges) {
    if ((*node_of)[g.i[e]] < 0 || (*node_of)[g.j[e]] < 0) continue;
    s.i.push_back((*node_of)[g.i[e]]);
    s.j.push_back((*node_of)[g.j[e]]);
    s.R_ij.push_back(g.R_ij[e]);
    s.prior.push_back(g.prior[e]);
    s.support.push_back(g.support[e]);
    s.source.push_back(g.source[e]);
  }
  return s;
}

bool Independent(const Graph& g, int e, int f) { return g.source[e] < 0 || g.source[e] != g.source[f]; }

// R_ij of observation e oriented from node a to node b (R_b = R R_a).
Eigen::Matrix3d Oriented(const Graph& g, int e, int a) {
  return g.i[e] == a ? g.R_ij[e] : Eigen::Matrix3d(g.R_ij[e].transpose());
}

// Stage 1's validation: observation e = (i, j) is validated if an observation of another
// source of the same image pair agrees with it, or two observations of other sources close
// the triangle (i, j, k) with it, within `tolerance` (radians).
std::vector<char> ValidatedObservations(const Graph& g, double tolerance) {
  const int n = static_cast<int>(g.ids.size());
  std::vector<std::map<int, std::vector<int>>> adjacent(n);  // node -> neighbour -> observations
  for (size_t e = 0; e < g.i.size(); ++e) {
    adjacent[g.i[e]][g.j[e]].push_back(static_cast<int>(e));
    adjacent[g.j[e]][g.i[e]].push_back(static_cast<int>(e));
  }
  std::vector<char> validated(g.i.size(), 0);  // char, not bool: written in parallel
  tbb::parallel_for(size_t(0), g.i.size(), [&](size_t k) {
    const int e = static_cast<int>(k);
    const int a = g.i[e], b = g.j[e];
    const Eigen::Matrix3d& R_ab = g.R_ij[e];
    for (int f : adjacent[a].at(b))
      if (f != e && Independent(g, e, f) && LogSO3(Oriented(g, f, a).transpose() * R_ab).norm() < tolerance) {
        validated[e] = 1;
        return;
      }
    // Triangles a -> b -> c -> a: R_ca R_bc R_ab ~ I.
    const auto& from_a = adjacent[a];
    for (const auto& [c, to_c] : adjacent[b]) {
      if (c == a) continue;
      auto back = from_a.find(c);
      if (back == from_a.end()) continue;
      for (int f : to_c) {
        if (!Independent(g, e, f)) continue;
        const Eigen::Matrix3d R_ac = Oriented(g, f, b) * R_ab;
        for (int h : back->second)
          if (Independent(g, e, h) && LogSO3(Oriented(g, h, a).transpose() * R_ac).norm() < tolerance) {
            validated[e] = 1;
            return;
          }
      }
    }
  });
  return validated;
}

// Node with the largest total support (ties: smallest id).
int GaugeNode(const Graph& g) {
  std::vector<double> total(g.ids.size(), 0.0);
  for (size_t e = 0; e < g.i.size(); ++e) {
    total[g.i[e]] += g.support[e] + g.prior[e];
    total[g.j[e]] += g.support[e] + g.prior[e];
  }
  return static_cast<int>(std::max_element(total.begin(), total.end()) - total.begin());
}

// Stage 1: chain the observations of a maximum spanning tree from the gauge node, the
// validated observations ranked above every unvalidated one, then by support. Several
// observations of one image pair: the best ranked one is used.
std::vector<Eigen::Matrix3d> SpanningTreeInit(const Graph& g, int root, double tolerance, int* tree_validated) {
  const int n = static_cast<int>(g.ids.size());
  const std::vector<char> validated = ValidatedObservations(g, tolerance);
  double top = 0.0;
  for (size_t e = 0; e < g.i.size(); ++e) top = std::max(top, g.support[e] + 1e-9 * g.prior[e]);
  std::vector<WeightedEdge> edges(g.i.size());
  for (size_t e = 0; e < g.i.size(); ++e)
    edges[e] = {g.i[e], g.j[e], g.support[e] + 1e-9 * g.prior[e] + (validated[e] ? 2.0 * top + 1.0 : 0.0)};
  std::vector<std::vector<int>> adjacent(n);
  *tree_validated = 0;
  for (int e : MaximumSpanningForest(n, edges)) {
    *tree_validated += validated[e];
    adjacent[g.i[e]].push_back(e);
    adjacent[g.j[e]].push_back(e);
  }
  std::vector<Eigen::Matrix3d> R(n, Eigen::Matrix3d::Identity());
  std::vector<bool> done(n, false);
  std::queue<int> queue;
  queue.push(root);
  done[root] = true;
  while (!queue.empty()) {
    const int a = queue.front();
    queue.pop();
    for (int e : adjacent[a]) {
      const bool forward = g.i[e] == a;  // R_j = R_ij R_i
      const int b = forward ? g.j[e] : g.i[e];
      if (done[b]) continue;
      R[b] = forward ? Eigen::Matrix3d(g.R_ij[e] * R[a]) : Eigen::Matrix3d(g.R_ij[e].transpose() * R[a]);
      done[b] = true;
      queue.push(b);
    }
  }
  return R;
}

// e_ij = Log(R_j^T R_ij R_i) for every observation (parallel, one slot per observation).
Eigen::MatrixXd Residuals(const Graph& g, const std::vector<Eigen::Matrix3d>& R) {
  Eigen::MatrixXd e(g.i.size(), 3);
  tbb::parallel_for(size_t(0), g.i.size(), [&](size_t k) {
    e.row(k) = LogSO3(R[g.j[k]].transpose() * g.R_ij[k] * R[g.i[k]]).transpose();
  });
  return e;
}

// R_i <- R_i Exp(x_i); returns the largest |x_i| (radians).
double ApplyUpdate(const Eigen::MatrixXd& x, std::vector<Eigen::Matrix3d>* R) {
  double step = 0.0;
  for (size_t n = 0; n < R->size(); ++n) {
    const Eigen::Vector3d w = x.row(n).transpose();
    (*R)[n] = ClosestRotation((*R)[n] * ExpSO3(w));
    step = std::max(step, w.norm());
  }
  return step;
}

std::vector<DifferenceEdge> Edges(const Graph& g, const std::vector<double>& weights) {
  std::vector<DifferenceEdge> edges(g.i.size());
  for (size_t e = 0; e < g.i.size(); ++e) edges[e] = {g.i[e], g.j[e], weights[e]};
  return edges;
}

// One relinearisation of the L1 stage: min_x sum_e prior_e |e_e - (x_j - x_i)| by inner
// IRLS with weights 1 / |r_e|.
bool SolveLinearisedL1(const Graph& g, const Eigen::MatrixXd& e, int inner, double scale, int gauge,
                       Eigen::MatrixXd* x) {
  const int n = static_cast<int>(g.ids.size());
  *x = Eigen::MatrixXd::Zero(n, 3);
  std::vector<double> w(g.i.size());
  for (int it = 0; it < inner; ++it) {
    for (size_t k = 0; k < g.i.size(); ++k) {
      const double r = (e.row(k) - (x->row(g.j[k]) - x->row(g.i[k]))).norm();
      w[k] = g.prior[k] * LossFunctionOptions{LossType::kL1, scale}.IrlsWeight(r);
    }
    if (!SolveDifferenceSystem(n, Edges(g, w), e, gauge, x)) return false;
  }
  return true;
}

}  // namespace

void ValidateRotationAveragingOptions(const RotationAveragingOptions& o) {
  if (const std::string m = o.Check(); !m.empty()) throw InputError("rotation averaging options: " + m);
}

double RelativeRotationResidualDeg(const RelativeRotation& o, const std::map<uint32_t, Eigen::Matrix3d>& rotations) {
  const Eigen::Matrix3d& R1 = rotations.at(o.image_id1);
  const Eigen::Matrix3d& R2 = rotations.at(o.image_id2);
  return RotationAngleDeg(o.R_21 * R1, R2);
}

bool AverageRotations(const std::vector<RelativeRotation>& observations, const RotationAveragingOptions& options,
                      std::map<uint32_t, Eigen::Matrix3d>* rotations, RotationAveragingSummary* summary_out) {
  ValidateRotationAveragingOptions(options);
  Timer timer;
  RotationAveragingSummary summary;
  auto finish = [&](bool ok, const std::string& message) {
    summary.success = ok;
    summary.message = message;
    summary.seconds = timer.Seconds();
    if (summary_out) *summary_out = summary;
    if (!ok) PGBA_LOG_WARN << "rotation averaging failed: " << message;
    return ok;
  };

  const Graph g = BuildGraph(observations);
  const int n = static_cast<int>(g.ids.size());
  summary.num_images = n;
  summary.num_observations = static_cast<int>(g.i.size());
  if (n == 0) return finish(false, "no observations");
  UnionFind uf(n);
  for (size_t e = 0; e < g.i.size(); ++e) uf.Union(g.i[e], g.j[e]);
  if (uf.SizeOf(0) != n) return finish(false, "the observation graph is not connected");

  const int gauge = GaugeNode(g);
  std::vector<Eigen::Matrix3d> R;
  if (options.spanning_tree_init) {
    R = SpanningTreeInit(g, gauge, options.init_consistency_deg * kDeg, &summary.tree_validated);
  } else {
    for (uint32_t id : g.ids) {
      auto it = rotations->find(id);
      if (it == rotations->end()) return finish(false, "no initial rotation for image " + std::to_string(id));
      R.push_back(it->second);
    }
  }

  const double scale = options.loss.scale * kDeg;
  Eigen::MatrixXd x;
  // Stage 2: L1.
  for (int it = 0; it < options.max_l1_iterations; ++it) {
    if (!SolveLinearisedL1(g, Residuals(g, R), options.l1_inner_iterations, scale, gauge, &x))
      return finish(false, "singular L1 system");
    ++summary.l1_iterations;
    if (ApplyUpdate(x, &R) < options.l1_step_tolerance_deg * kDeg) break;
  }
  // Stage 3: IRLS with the robust loss.
  auto irls = [&](const Graph& graph, int root, std::vector<Eigen::Matrix3d>* rot) {
    std::vector<double> w(graph.i.size());
    summary.converged = false;
    for (int it = 0; it < options.max_irls_iterations; ++it) {
      const Eigen::MatrixXd e = Residuals(graph, *rot);
      for (size_t k = 0; k < graph.i.size(); ++k)
        w[k] = graph.prior[k] * LossFunctionOptions{options.loss.type, scale}.IrlsWeight(e.row(k).norm());
      if (!SolveDifferenceSystem(static_cast<int>(graph.ids.size()), Edges(graph, w), e, root, &x)) return false;
      ++summary.irls_iterations;
      summary.last_step_deg = ApplyUpdate(x, rot) / kDeg;
      if (summary.last_step_deg < options.step_tolerance_deg) {
        summary.converged = true;
        break;
      }
    }
    return true;
  };
  if (!irls(g, gauge, &R)) return finish(false, "singular IRLS system");

  // Residuals; stage 4: outlier observations excluded, IRLS again on the largest component of
  // the inliers.
  std::vector<double> deg(g.i.size());
  {
    const Eigen::MatrixXd e = Residuals(g, R);
    for (size_t k = 0; k < g.i.size(); ++k) deg[k] = e.row(k).norm() / kDeg;
  }
  std::vector<int> inliers;
  for (size_t k = 0; k < g.i.size(); ++k)
    if (deg[k] <= options.inlier_threshold_deg) inliers.push_back(static_cast<int>(k));
  summary.num_inliers = static_cast<int>(inliers.size());
  summary.num_outliers = summary.num_observations - summary.num_inliers;
  const Graph* final_graph = &g;
  Graph inlier_graph;
  if (options.exclude_outliers && summary.num_outliers > 0) {
    UnionFind in(n);
    for (int k : inliers) in.Union(g.i[k], g.j[k]);
    int root = 0;
    for (int k = 0; k < n; ++k)
      if (in.SizeOf(k) > in.SizeOf(root)) root = k;
    std::vector<bool> keep(n);
    for (int k = 0; k < n; ++k) {
      keep[k] = in.Find(k) == in.Find(root);
      if (!keep[k]) summary.images_without_inliers.push_back(g.ids[k]);
    }
    std::vector<int> node_of;
    inlier_graph = Subgraph(g, inliers, keep, &node_of);
    std::vector<Eigen::Matrix3d> R_in;
    for (int k = 0; k < n; ++k)
      if (keep[k]) R_in.push_back(R[k]);
    const int inlier_gauge = keep[gauge] ? node_of[gauge] : GaugeNode(inlier_graph);
    if (!inlier_graph.i.empty() && !irls(inlier_graph, inlier_gauge, &R_in))
      return finish(false, "singular IRLS system on the inliers");
    R = std::move(R_in);
    final_graph = &inlier_graph;
    const Eigen::MatrixXd e = Residuals(inlier_graph, R);
    deg.resize(inlier_graph.i.size());
    for (size_t k = 0; k < inlier_graph.i.size(); ++k) deg[k] = e.row(k).norm() / kDeg;
    if (!summary.images_without_inliers.empty())
      PGBA_LOG_DEBUG << "rotation averaging: " << summary.images_without_inliers.size()
                    << " images have no inlier observation connecting them to the others";
  }
  if (!deg.empty()) {
    std::nth_element(deg.begin(), deg.begin() + deg.size() / 2, deg.end());
    summary.residual_median_deg = deg[deg.size() / 2];
  }
  for (uint32_t id : summary.images_without_inliers) rotations->erase(id);
  for (size_t k = 0; k < final_graph->ids.size(); ++k) (*rotations)[final_graph->ids[k]] = R[k];
  PGBA_LOG_DEBUG << "rotation averaging: " << final_graph->ids.size() << " images, " << summary.num_observations
                << " observations (" << summary.tree_validated << " of the tree's edges validated), "
                << summary.l1_iterations << " L1 + " << summary.irls_iterations << " IRLS iterations, "
                << summary.num_outliers << " outliers" << (options.exclude_outliers ? " excluded" : "")
                << ", median residual " << summary.residual_median_deg << " deg";
  return finish(true, summary.converged ? "converged" : "iteration limit reached");
}

std::string RotationAveragingOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init.rotation"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
