// Per-frame latency and setup of the model-based reconstructors on the medium mesh (2,720
// triangles), 64x64 pixels: the figures issue 5 sets targets for.
#include <benchmark/benchmark.h>
#include <tbb/task_arena.h>

#include <random>

#include "eitbench/jacobian.h"
#include "eitbench/solvers.h"

namespace {
using namespace eitbench;

struct Fixture {
  std::shared_ptr<const ForwardModel> model =
      std::make_shared<const ForwardModel>(generate_disk_mesh({16, MeshDensity::medium}));
  std::shared_ptr<const LinearProblem> problem =
      std::make_shared<const LinearProblem>(make_linear_problem(model, 1.0, PixelGrid(64, 1.0)));
  Eigen::VectorXd frame = problem->A * problem->from_image(circles_image(
                                           PixelGrid(64, 1.0), {{0.3, 0.2, 0.2, 0.5}}, 1.0));
};
const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_LinearProblemSetup(benchmark::State& state) {  // forward, Jacobian, pixel map
  const auto& f = fixture();
  for (auto _ : state)
    benchmark::DoNotOptimize(make_linear_problem(f.model, 1.0, PixelGrid(64, 1.0)).A.data());
}

void BM_TikhonovSetup(
    benchmark::State& state) {  // prior, G, its eigendecomposition, lambda's matrix
  const auto& f = fixture();
  TikhonovOptions o;
  o.prior = static_cast<Prior>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(Tikhonov(f.problem, o).lambda());
  state.SetLabel(Tikhonov(f.problem, o).name());
}

void BM_TikhonovFrame(benchmark::State& state) {
  const auto& f = fixture();
  TikhonovOptions o;
  o.prior = Prior::noser;
  o.single_precision = state.range(0) == 1;
  const Tikhonov t(f.problem, o);
  for (auto _ : state) benchmark::DoNotOptimize(t.reconstruct(f.frame).data());
  state.SetLabel(o.single_precision ? "single precision" : "double precision");
}

void BM_GreitSetup(benchmark::State& state) {  // 1,000 training targets, their products, R
  const auto& f = fixture();
  for (auto _ : state) benchmark::DoNotOptimize(Greit(f.problem, {}).settings().size());
}

void BM_GreitFrame(benchmark::State& state) {
  const auto& f = fixture();
  const Greit greit(f.problem, {});
  for (auto _ : state) benchmark::DoNotOptimize(greit.reconstruct(f.frame).data());
}

void BM_TotalVariationFrame(benchmark::State& state) {
  const auto& f = fixture();
  const TotalVariation tv(f.problem, {});
  TotalVariation::Report report;
  // Arg = threads: the solver splits its products over two tasks; 1 shows the serial cost.
  tbb::task_arena arena(static_cast<int>(state.range(0)));
  for (auto _ : state)
    arena.execute([&] { benchmark::DoNotOptimize(tv.solve(f.frame, &report).data()); });
  state.counters["iterations"] = report.iterations;
}

void BM_GaussNewtonFrame(benchmark::State& state) {  // to convergence, difference mode
  const auto& f = fixture();
  const GaussNewton gn(f.problem, {});
  GaussNewton::Report report;
  for (auto _ : state) benchmark::DoNotOptimize(gn.solve(f.frame, &report).data());
  state.counters["iterations"] = report.iterations;
}

BENCHMARK(BM_LinearProblemSetup)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TikhonovSetup)->DenseRange(0, 2)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_TikhonovFrame)->Arg(1)->Arg(0)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GreitSetup)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GreitFrame)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TotalVariationFrame)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GaussNewtonFrame)->Unit(benchmark::kMillisecond);

}  // namespace
