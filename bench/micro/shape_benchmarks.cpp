// Per-frame latency of the shape fit (the "where is the touch" targets: linear <= 20 ms, full
// <= 200 ms a frame on 2 cores), on the medium mesh, for a frame of two touches simulated by the
// FEM on the same mesh. Every K from 1 to 4 is fitted, as in a run.
#include <benchmark/benchmark.h>

#include "eitbench/jacobian.h"
#include "eitbench/solvers.h"

namespace {
using namespace eitbench;

struct ShapeFixture {
  std::shared_ptr<const ForwardModel> model =
      std::make_shared<const ForwardModel>(generate_disk_mesh({16, MeshDensity::medium}));
  std::shared_ptr<const LinearProblem> problem =
      std::make_shared<const LinearProblem>(make_linear_problem(model, 0.05, PixelGrid(64, 1.0)));
  Eigen::VectorXd frame = touch_frame({{0.4, 0.3, 0.15, 0.01}, {-0.35, -0.2, 0.12, 0.02}});

  Eigen::VectorXd touch_frame(const std::vector<Circle>& circles) const {
    const Protocol& protocol = model->protocol();
    auto reduced = [&](const Eigen::VectorXd& sigma) {
      return protocol.reduce(model->frame(model->solve(sigma)), MeasurementOrder::rotating);
    };
    const Mesh& mesh = model->mesh();
    return reduced(conductivity_from_circles(mesh, circles, 0.05)) -
           reduced(Eigen::VectorXd::Constant(mesh.num_triangles(), 0.05));
  }
};
const ShapeFixture& fixture() {
  static const ShapeFixture f;
  return f;
}

void BM_ShapeFrame(benchmark::State& state) {
  const auto& f = fixture();
  ShapeOptions o;
  o.forward = state.range(0) == 1 ? ShapeForward::full : ShapeForward::linear;
  const ShapeReconstructor shape(f.problem, o);
  ShapeFit fit;
  for (auto _ : state) benchmark::DoNotOptimize((fit = shape.fit_circles(f.frame)).rss);
  state.counters["K"] = static_cast<double>(fit.circles.size());
  state.counters["iterations"] = fit.iterations;
  state.SetLabel(to_string(o.forward));
}

BENCHMARK(BM_ShapeFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
