// The paper's simulated experiment (Henein et al. 2020, Table I): what `dslam sim --scenario paper`
// must show, averaged over seeds 1..10.
#include <gtest/gtest.h>

#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

struct Means {
  double omte = 0, omre = 0, rte = 0, rse = 0;
};

std::map<Method, Means> MeanOverSeeds(MotionMode mode, int seeds, const std::vector<Method>& methods) {
  std::map<Method, Means> means;
  for (int seed = 1; seed <= seeds; ++seed) {
    ScenarioOptions opt;
    opt.seed = seed;
    RunConfig config;
    config.backend.default_mode = mode;
    RunSequenceOptions run;
    run.methods = methods;
    for (const auto& [method, outcome] : RunSequence(MakeScenario("paper", opt), config, run)) {
      const auto& m = outcome.metrics;
      Means& acc = means[method];
      acc.omte += *m.objects->omte_pct / seeds;
      acc.omre += *m.objects->omre_deg_per_m / seeds;
      acc.rte += *m.camera.rte_pct / seeds;
      acc.rse += *m.rse_pct / seeds;
    }
  }
  return means;
}

TEST(PaperScenario, OursCutsObjectMotionErrorsOfSlamMotBySixtyPercent) {
  auto means = MeanOverSeeds(MotionMode::kConstant, 10, {Method::kOurs, Method::kSlamMot});
  const Means& ours = means[Method::kOurs];
  const Means& mot = means[Method::kSlamMot];
  std::cout << "paper, seeds 1..10: OMTE ours " << ours.omte << " % vs SLAM+MOT " << mot.omte << " %; OMRE "
            << ours.omre << " vs " << mot.omre << " deg/m; RTE " << ours.rte << " vs " << mot.rte << " %; RSE "
            << ours.rse << " vs " << mot.rse << " %\n";
  EXPECT_LE(ours.omte, 0.4 * mot.omte);
  EXPECT_LE(ours.omre, 0.4 * mot.omre);
  EXPECT_LT(ours.rte, mot.rte);
  EXPECT_LT(ours.rse, mot.rse);
}

TEST(PaperScenario, ConstantMotionModelBeatsPerStep) {
  const Means constant = MeanOverSeeds(MotionMode::kConstant, 3, {Method::kOurs})[Method::kOurs];
  const Means per_step = MeanOverSeeds(MotionMode::kPerStep, 3, {Method::kOurs})[Method::kOurs];
  std::cout << "paper, seeds 1..3: OMTE constant " << constant.omte << " % vs per-step " << per_step.omte << " %\n";
  EXPECT_LT(constant.omte, per_step.omte);
}

}  // namespace
}  // namespace dslam
