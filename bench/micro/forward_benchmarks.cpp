// Microbenchmarks of the physics, per mesh density: mesh generation, model setup (assembly pattern
// and symbolic analysis), one forward solve of all L drives, and the Jacobian.
//   build/eitbench_microbench --benchmark_out=bench.json --benchmark_out_format=json
#include <benchmark/benchmark.h>

#include "eitbench/jacobian.h"

namespace {
using namespace eitbench;

MeshDensity density_of(const benchmark::State& state) {
  return static_cast<MeshDensity>(state.range(0));
}

const Mesh& cached_mesh(MeshDensity density) {
  static const Mesh meshes[3] = {generate_disk_mesh({16, MeshDensity::coarse}),
                                 generate_disk_mesh({16, MeshDensity::medium}),
                                 generate_disk_mesh({16, MeshDensity::fine})};
  return meshes[static_cast<int>(density)];
}

void label(benchmark::State& state, const Mesh& mesh) {
  state.SetLabel(to_string(density_of(state)) + ", " + std::to_string(mesh.num_triangles()) +
                 " triangles");
}

void BM_MeshGeneration(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(generate_disk_mesh({16, density_of(state)}));
  label(state, cached_mesh(density_of(state)));
}

void BM_ModelSetup(benchmark::State& state) {
  const Mesh& mesh = cached_mesh(density_of(state));
  for (auto _ : state) benchmark::DoNotOptimize(ForwardModel(mesh));
  label(state, mesh);
}

void BM_Forward(benchmark::State& state) {  // assembly, numeric factorisation, 16 solves
  const Mesh& mesh = cached_mesh(density_of(state));
  const ForwardModel model(mesh);
  const Eigen::VectorXd sigma = Eigen::VectorXd::Ones(mesh.num_triangles());
  for (auto _ : state) benchmark::DoNotOptimize(model.solve(sigma));
  label(state, mesh);
}

void BM_Frame(benchmark::State& state) {  // forward plus the 208 differences
  const Mesh& mesh = cached_mesh(density_of(state));
  const ForwardModel model(mesh);
  const Eigen::VectorXd sigma = Eigen::VectorXd::Ones(mesh.num_triangles());
  for (auto _ : state) benchmark::DoNotOptimize(model.frame(sigma));
  label(state, mesh);
}

void BM_Jacobian(benchmark::State& state) {  // forward included
  const Mesh& mesh = cached_mesh(density_of(state));
  const ForwardModel model(mesh);
  const Eigen::VectorXd sigma = Eigen::VectorXd::Ones(mesh.num_triangles());
  for (auto _ : state) benchmark::DoNotOptimize(model.jacobian(sigma));
  label(state, mesh);
}

void BM_PixelMap(benchmark::State& state) {
  const Mesh& mesh = cached_mesh(density_of(state));
  const PixelGrid grid(64, 1.0);
  for (auto _ : state) benchmark::DoNotOptimize(pixel_to_element(mesh, grid));
  label(state, mesh);
}

void BM_PixelJacobian(benchmark::State& state) {  // J_elem * P, after the forward solve
  const Mesh& mesh = cached_mesh(density_of(state));
  const ForwardModel model(mesh);
  const auto P = pixel_to_element(mesh, PixelGrid(64, 1.0));
  const Eigen::MatrixXd J = model.jacobian(Eigen::VectorXd::Ones(mesh.num_triangles()));
  for (auto _ : state) {
    Eigen::MatrixXd Jp = J * P;
    benchmark::DoNotOptimize(Jp.data());
  }
  label(state, mesh);
}

#define DENSITIES ->DenseRange(0, 2)->Unit(benchmark::kMillisecond)
BENCHMARK(BM_MeshGeneration) DENSITIES;
BENCHMARK(BM_ModelSetup) DENSITIES;
BENCHMARK(BM_Forward) DENSITIES;
BENCHMARK(BM_Frame) DENSITIES;
BENCHMARK(BM_Jacobian) DENSITIES;
BENCHMARK(BM_PixelMap) DENSITIES;
BENCHMARK(BM_PixelJacobian) DENSITIES;

}  // namespace
