#include "averaging/translation_averaging.h"

#include <algorithm>
#include <cmath>

#include "pgba/io/option_ranges.h"
#include "averaging/connectivity.h"
#include "averaging/difference_system.h"
#include "averaging/similarity.h"
#include "averaging/translation_refinement.h"
#include "pgba/util/error.h"
#include "pgba/util/logging.h"
#include "pgba/util/timer.h"
#include "pgba/util/upper_median.h"

namespace pgba {
namespace {

// Step 1: every baseline of triplet t observes the length l_ab of the pair (a, b):
// log l_ab - log S_t = log|v^t_ab|. Unknowns: log S_t per triplet and log l_ab per image
// pair, a difference system on the bipartite triplet-pair graph (sparse: each triplet has
// three neighbours), connected exactly when the triplets are connected through shared pairs.
bool SolveTripletSizes(const std::vector<TripletBaseline>& baselines, int num_triplets,
                       const TranslationAveragingOptions& options, std::vector<double>* sizes,
                       TranslationAveragingSummary* summary) {
  std::map<std::pair<int, int>, int> pair_node;  // image pair -> node after the triplets
  std::vector<DifferenceEdge> edges;
  std::vector<double> obs, prior;
  for (const TripletBaseline& bl : baselines) {
    const double length = bl.v.norm();  // relative to the triplet's largest baseline
    if (!(length > 1e-9)) continue;
    auto [it, inserted] = pair_node.emplace(std::minmax(bl.a, bl.b), num_triplets + static_cast<int>(pair_node.size()));
    edges.push_back({bl.triplet, it->second, 0.0});
    obs.push_back(std::log(length));
    // A short baseline (relative to its triplet) has a noisy length.
    prior.push_back(length * length);
  }
  summary->scale_links = static_cast<int>(edges.size());
  const int num_nodes = num_triplets + static_cast<int>(pair_node.size());
  const Eigen::Map<const Eigen::VectorXd> b(obs.data(), obs.size());
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(num_nodes, 1), x_new;
  for (int it = 0; it < options.max_irls_iterations; ++it) {
    for (size_t e = 0; e < edges.size(); ++e) {
      const double r = obs[e] - (x(edges[e].j, 0) - x(edges[e].i, 0));
      edges[e].weight = prior[e] * options.scale_loss.IrlsWeight(r);
    }
    if (!SolveDifferenceSystem(num_nodes, edges, b, 0, &x_new)) return false;
    const double change = (x_new - x).cwiseAbs().maxCoeff();
    x = x_new;
    ++summary->scale_iterations;
    if (change < options.irls_tolerance) break;
  }
  sizes->resize(num_triplets);
  for (int t = 0; t < num_triplets; ++t) (*sizes)[t] = std::exp(x(t, 0));
  return true;
}

// Relative residual |C_b - C_a - S_t v| / S_t of every baseline.
std::vector<double> RelativeResiduals(const std::vector<TripletBaseline>& baselines, const Eigen::MatrixXd& C,
                                      const std::vector<double>& S) {
  std::vector<double> r(baselines.size());
  for (size_t k = 0; k < baselines.size(); ++k) {
    const TripletBaseline& bl = baselines[k];
    const Eigen::Vector3d d = (C.row(bl.b) - C.row(bl.a)).transpose();
    r[k] = (d - S[bl.triplet] * bl.v).norm() / S[bl.triplet];
  }
  return r;
}

// Step 2: C_b - C_a = S_t v by IRLS on the relative residuals.
bool SolveCentres(const std::vector<TripletBaseline>& baselines, int num_nodes, const std::vector<double>& S,
                  const TranslationAveragingOptions& options, Eigen::MatrixXd* C,
                  TranslationAveragingSummary* summary) {
  std::vector<DifferenceEdge> edges(baselines.size());
  Eigen::MatrixXd b(baselines.size(), 3);
  for (size_t k = 0; k < baselines.size(); ++k) {
    edges[k] = {baselines[k].a, baselines[k].b, 1.0};
    b.row(k) = S[baselines[k].triplet] * baselines[k].v.transpose();
  }
  std::vector<double> r(baselines.size(), 0.0);
  *C = Eigen::MatrixXd::Zero(num_nodes, 3);
  Eigen::MatrixXd C_new;
  for (int it = 0; it < std::max(1, options.max_irls_iterations); ++it) {
    for (size_t k = 0; k < baselines.size(); ++k) {
      const double s = S[baselines[k].triplet];
      edges[k].weight = options.centre_loss.IrlsWeight(r[k]) / (s * s);
    }
    if (!SolveDifferenceSystem(num_nodes, edges, b, 0, &C_new)) return false;
    ++summary->centre_iterations;
    double change = 0.0;
    for (const TripletBaseline& bl : baselines)
      change = std::max(change, (C_new.row(bl.a) - C->row(bl.a)).norm() / S[bl.triplet]);
    *C = C_new;
    r = RelativeResiduals(baselines, *C, S);
    if (it > 0 && change < options.irls_tolerance) break;
  }
  return true;
}

}  // namespace

void ValidateTranslationAveragingOptions(const TranslationAveragingOptions& o) {
  if (const std::string m = o.Check(); !m.empty()) throw InputError("translation averaging options: " + m);
}

bool AverageTranslations(const std::vector<LocalMotion>& triplets, const std::vector<TwoViewGeometry>& pairs,
                         const std::map<uint32_t, Eigen::Matrix3d>& rotations,
                         const TranslationAveragingOptions& options, std::map<uint32_t, Eigen::Vector3d>* centres,
                         TranslationAveragingSummary* summary_out) {
  ValidateTranslationAveragingOptions(options);
  Timer timer;
  TranslationAveragingSummary summary;
  auto finish = [&](bool ok, const std::string& message) {
    summary.success = ok;
    summary.message = message;
    summary.seconds = timer.Seconds();
    if (summary_out) *summary_out = summary;
    if (!ok) PGBA_LOG_WARN << "translation averaging failed: " << message;
    return ok;
  };

  // Image nodes and the triplets' baselines in the global orientation.
  std::map<uint32_t, int> node;
  for (const LocalMotion& t : triplets) {
    if (!HasDistinctImages(t)) return finish(false, "a triplet has repeated images");
    for (uint32_t id : t.image_ids) {
      if (!rotations.count(id)) return finish(false, "no rotation for image " + std::to_string(id));
      node.emplace(id, 0);
    }
  }
  if (triplets.empty()) return finish(false, "no triplets");
  std::vector<uint32_t> ids;
  for (auto& [id, n] : node) {
    n = static_cast<int>(ids.size());
    ids.push_back(id);
  }
  const int num_triplets = static_cast<int>(triplets.size());
  std::vector<TripletBaseline> baselines;
  std::vector<double> local_size(num_triplets);  // L_t
  for (int t = 0; t < num_triplets; ++t) {
    const LocalMotion& tr = triplets[t];
    const Eigen::Matrix3d alpha = AverageTripletRotation(tr, rotations);
    double L = 0.0;
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b) L = std::max(L, (tr.local_poses[b].C() - tr.local_poses[a].C()).norm());
    if (!(L > 0.0) || !std::isfinite(L)) return finish(false, "triplet " + std::to_string(t) + " has no baseline");
    local_size[t] = L;
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        baselines.push_back({t, node[tr.image_ids[a]], node[tr.image_ids[b]],
                             alpha.transpose() * (tr.local_poses[b].C() - tr.local_poses[a].C()) / L});
  }
  summary.num_images = static_cast<int>(ids.size());
  summary.num_triplets = num_triplets;

  Timer step;
  std::vector<double> S;
  if (!SolveTripletSizes(baselines, num_triplets, options, &S, &summary))
    return finish(false, "the triplets are not connected through shared image pairs");
  summary.seconds_scales = step.Seconds();
  step.Restart();
  Eigen::MatrixXd C;
  if (!SolveCentres(baselines, static_cast<int>(ids.size()), S, options, &C, &summary))
    return finish(false, "singular centre system");

  summary.seconds_centres = step.Seconds();
  step.Restart();
  if (options.refine) {
    std::vector<PairDirection> directions;
    if (options.use_pair_directions) {
      for (const TwoViewGeometry& p : pairs) {
        auto i = node.find(p.image_id1), j = node.find(p.image_id2);
        if (i == node.end() || j == node.end() || i == j || !(p.t_21.norm() > 0) || !p.t_21.allFinite()) continue;
        // t_21 = R_2 (C_1 - C_2)  =>  C_2 - C_1 = -R_2^T t_21.
        const Eigen::Vector3d u = -(rotations.at(p.image_id2).transpose() * p.t_21).normalized();
        directions.push_back({i->second, j->second, u});
      }
    }
    summary.num_pairs = static_cast<int>(directions.size());
    // Gauge of the refinement: the best fitting triplet of step 2 keeps its size.
    const std::vector<double> r = RelativeResiduals(baselines, C, S);
    std::vector<double> worst(num_triplets, 0.0);
    for (size_t k = 0; k < baselines.size(); ++k) worst[baselines[k].triplet] = std::max(worst[baselines[k].triplet], r[k]);
    const int fixed_triplet = static_cast<int>(std::min_element(worst.begin(), worst.end()) - worst.begin());
    summary.refine_iterations = RefineCentres(baselines, directions, options, baselines[3 * fixed_triplet].a,
                                              fixed_triplet, &C, &S);
    if (!C.allFinite()) return finish(false, "refinement diverged");
  }
  summary.seconds_refine = step.Seconds();
  summary.residual_median_rel = UpperMedian(RelativeResiduals(baselines, C, S));

  // Gauge: centroid 0 and median lambda_t = 1, lambda_t = L_t / S_t being the global->local
  // scale of triplet t (scaling the centres by f divides every lambda_t by f).
  std::vector<double> lambdas(S.size());
  for (size_t t = 0; t < S.size(); ++t) lambdas[t] = local_size[t] / S[t];
  const double f = UpperMedian(lambdas);
  const Eigen::RowVector3d centroid = C.colwise().mean();
  for (size_t n = 0; n < ids.size(); ++n) (*centres)[ids[n]] = f * (C.row(n) - centroid).transpose();
  PGBA_LOG_DEBUG << "translation averaging: " << ids.size() << " images, " << num_triplets << " triplets, "
                << summary.num_pairs << " pair directions, median relative residual " << summary.residual_median_rel;
  return finish(true, "ok");
}

std::string TranslationAveragingOptions::Check() const {
  if (const std::string m = CheckRanges(*this, "global_init.translation"); !m.empty()) return m;
  return "";
}

}  // namespace pgba
