// CEM forward model. Unknowns: the node potentials u (node 0 grounded, so the system is SPD) and
// the L electrode potentials U. With phi_i the hat functions and z_e the contact impedances:
//   [ K(sigma) + A_Z   A_W ] [u]   [0]
//   [ A_W^T            A_D ] [U] = [I]
//   A_Z = sum_e 1/z_e int_e phi_i phi_j,  A_W(i,e) = -1/z_e int_e phi_i,  A_D = diag(|e_e| / z_e).
// Only K depends on sigma: the electrode blocks are assembled once, and each triangle's six
// stiffness entries are scattered through precomputed positions in the CSC arrays.
#include "eitbench/jacobian/forward_model.h"

#include <cholmod.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "eitbench/jacobian/error.h"

#include "drive_patterns.h"

namespace eitbench {
namespace {

constexpr int kLocalPairs = 6;  // (0,0) (1,1) (2,2) (0,1) (0,2) (1,2)
constexpr int kPairI[kLocalPairs] = {0, 1, 2, 0, 0, 1};
constexpr int kPairJ[kLocalPairs] = {0, 1, 2, 1, 2, 2};

class Common {
 public:
  Common() {
    cholmod_start(&c_);
    c_.print = 0;
    c_.error_handler = nullptr;
  }
  ~Common() { cholmod_finish(&c_); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
  cholmod_common* get() { return &c_; }

 private:
  cholmod_common c_;
};

// A numeric factor with its CHOLMOD workspace. Reusing one across solves avoids allocating (and
// page-faulting in) megabytes for every conductivity.
// What one solve needs, kept between solves: the factor (with the symbolic analysis), the
// system's values, and CHOLMOD's solution and work arrays (cholmod_solve2 reuses them when their
// size fits), so that a solve allocates nothing after the first.
struct Workspace {
  Common common;
  cholmod_factor* factor = nullptr;
  std::vector<double> values;
  cholmod_dense *X = nullptr, *Y = nullptr, *E = nullptr;
  ~Workspace() {
    if (factor) cholmod_free_factor(&factor, common.get());
    for (cholmod_dense** d : {&X, &Y, &E})
      if (*d) cholmod_free_dense(d, common.get());
  }
};

}  // namespace

struct ForwardModel::Impl {
  Mesh mesh;
  ForwardOptions options;
  Protocol protocol;
  MeasurementProtocol measurement;
  Eigen::VectorXd z;     // contact impedance per electrode
  Eigen::VectorXd area;  // per triangle
  Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor> grad;  // dphi/dx (3), dphi/dy (3)
  Eigen::Matrix<double, Eigen::Dynamic, kLocalPairs, Eigen::RowMajor> stiffness;  // sigma = 1
  Eigen::Matrix<int, Eigen::Dynamic, kLocalPairs, Eigen::RowMajor> scatter;  // value index or -1
  // The system's lower triangle in CSC form (int indices, as cholmod_sparse with itype INT).
  std::vector<int> col_ptr, row_idx;
  std::vector<double> base_values;  // the sigma-independent electrode blocks
  int dofs = 0;
  Eigen::MatrixXd rhs;  // dofs x L: drive d puts +I on electrode d and -I on d + 1
  mutable Common analysis_common;
  cholmod_factor* symbolic = nullptr;
  // Idle workspaces: solve() takes one (or makes one) and gives it back, so concurrent solves
  // never share a factor.
  mutable std::mutex pool_mutex;
  mutable std::vector<std::unique_ptr<Workspace>> pool;

  std::unique_ptr<Workspace> take() const {
    {
      std::lock_guard<std::mutex> lock(pool_mutex);
      if (!pool.empty()) {
        auto w = std::move(pool.back());
        pool.pop_back();
        return w;
      }
    }
    auto w = std::make_unique<Workspace>();
    w->factor = cholmod_copy_factor(symbolic, w->common.get());
    if (!w->factor) throw std::runtime_error("CHOLMOD: out of memory");
    return w;
  }
  // Assembles and factorises for sigma and solves every drive, in a workspace from the pool: the
  // solution is its X (dofs x L). Give it back when done.
  std::unique_ptr<Workspace> solve(const Eigen::VectorXd& sigma) const;
  // d v / d sigma for the values `patterns` describe (drive_patterns.h), of every triangle or of
  // `elements` only.
  Eigen::MatrixXd jacobian(const ForwardSolution& s, const detail::DrivePatterns& patterns,
                           const std::vector<int>& elements) const;
  void give_back(std::unique_ptr<Workspace> w) const {
    std::lock_guard<std::mutex> lock(pool_mutex);
    pool.push_back(std::move(w));
  }
  // read(U) for sigma's electrode potentials U (electrode x adjacent drive), read in place from
  // the solve's last L rows: no node potentials are copied out (CHOLMOD's leading dimension may
  // exceed dofs).
  template <typename Read>
  Eigen::VectorXd from_electrodes(const Eigen::VectorXd& sigma, const Read& read) const {
    std::unique_ptr<Workspace> w = solve(sigma);
    const int L = mesh.num_electrodes();
    const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> U(
        static_cast<const double*>(w->X->x) + dofs - L, L, L,
        Eigen::OuterStride<>(static_cast<Eigen::Index>(w->X->d)));
    Eigen::VectorXd v = read(U);
    give_back(std::move(w));
    return v;
  }

  explicit Impl(const Mesh& m, const ForwardOptions& o)
      : mesh(m),
        options(o),
        protocol(m.num_electrodes()),
        measurement(o.protocol ? *o.protocol : adjacent_protocol(m.num_electrodes())) {}
  ~Impl() {
    pool.clear();
    if (symbolic) cholmod_free_factor(&symbolic, analysis_common.get());
  }

  int node_dof(int node) const { return node - 1; }  // node 0 is grounded: -1
  int electrode_dof(int e) const { return mesh.num_nodes() - 1 + e; }

  void build();
  void element_geometry();
  void sparsity_pattern();
  int position(int r, int c) const;  // index of (r, c) or (c, r) in row_idx; -1 for ground
  void scatter_positions();
  void electrode_blocks();
  void analyse();
  cholmod_sparse view(std::vector<double>& values) const;
};

// The assembly is split by what each part prepares once per mesh: element geometry, the system's
// sparsity pattern, where each element's contributions land in it, and the electrodes' fixed
// blocks; then CHOLMOD's symbolic analysis, shared by every solve.
void ForwardModel::Impl::build() {
  dofs = mesh.num_nodes() - 1 + mesh.num_electrodes();
  element_geometry();
  sparsity_pattern();
  scatter_positions();
  electrode_blocks();
  analyse();
}

// Each triangle's area, hat-function gradients and the 6 entries of its unit-conductivity
// stiffness matrix.
void ForwardModel::Impl::element_geometry() {
  const int T = mesh.num_triangles();
  area.resize(T);
  grad.resize(T, 6);
  stiffness.resize(T, kLocalPairs);
  for (int t = 0; t < T; ++t) {
    Eigen::Vector2d p[3];
    for (int k = 0; k < 3; ++k) p[k] = mesh.nodes.row(mesh.triangles(t, k));
    const double a2 = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
    area[t] = 0.5 * a2;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector2d& q = p[(k + 1) % 3];
      const Eigen::Vector2d& r = p[(k + 2) % 3];
      grad(t, k) = (q.y() - r.y()) / a2;
      grad(t, 3 + k) = (r.x() - q.x()) / a2;
    }
    for (int q = 0; q < kLocalPairs; ++q)
      stiffness(t, q) = area[t] * (grad(t, kPairI[q]) * grad(t, kPairJ[q]) +
                                   grad(t, 3 + kPairI[q]) * grad(t, 3 + kPairJ[q]));
  }
}

// The lower triangle's pattern (compressed columns): element couplings, and each electrode's
// coupling to itself and to the nodes under it.
void ForwardModel::Impl::sparsity_pattern() {
  std::vector<std::vector<int>> rows_of_col(dofs);
  auto touch = [&](int r, int c) {
    if (r < 0 || c < 0) return;
    if (r < c) std::swap(r, c);
    rows_of_col[c].push_back(r);
  };
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int q = 0; q < kLocalPairs; ++q)
      touch(node_dof(mesh.triangles(t, kPairI[q])), node_dof(mesh.triangles(t, kPairJ[q])));
  for (int e = 0; e < mesh.num_electrodes(); ++e) {
    const Electrode& el = mesh.electrodes[e];
    touch(electrode_dof(e), electrode_dof(e));
    const std::vector<int> nodes = el.is_point() ? std::vector<int>{el.point_node} : [&] {
      std::vector<int> n;
      for (const auto& s : el.segments) n.insert(n.end(), {s[0], s[1]});
      return n;
    }();
    for (int n : nodes) {
      touch(node_dof(n), node_dof(n));
      touch(electrode_dof(e), node_dof(n));
    }
    for (const auto& s : el.segments) touch(node_dof(s[0]), node_dof(s[1]));
  }
  col_ptr.assign(dofs + 1, 0);
  row_idx.clear();
  for (int c = 0; c < dofs; ++c) {
    auto& rows = rows_of_col[c];
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
    row_idx.insert(row_idx.end(), rows.begin(), rows.end());
    col_ptr[c + 1] = static_cast<int>(row_idx.size());
  }
}

int ForwardModel::Impl::position(int r, int c) const {
  if (r < 0 || c < 0) return -1;
  if (r < c) std::swap(r, c);
  const auto begin = row_idx.begin() + col_ptr[c], end = row_idx.begin() + col_ptr[c + 1];
  return static_cast<int>(std::lower_bound(begin, end, r) - row_idx.begin());
}

void ForwardModel::Impl::scatter_positions() {
  scatter.resize(mesh.num_triangles(), kLocalPairs);
  for (int t = 0; t < mesh.num_triangles(); ++t)
    for (int q = 0; q < kLocalPairs; ++q)
      scatter(t, q) =
          position(node_dof(mesh.triangles(t, kPairI[q])), node_dof(mesh.triangles(t, kPairJ[q])));
}

// The complete electrode model's blocks, which do not depend on the conductivity: per segment of
// length len under electrode e with contact impedance z_e, the boundary mass matrix / z_e on its
// nodes, -len / (2 z_e) between them and U_e, and |e| / z_e on U_e.
void ForwardModel::Impl::electrode_blocks() {
  base_values.assign(row_idx.size(), 0.0);
  auto add = [&](int r, int c, double v) {
    const int pos = position(r, c);
    if (pos >= 0) base_values[pos] += v;
  };
  for (int e = 0; e < mesh.num_electrodes(); ++e) {
    const Electrode& el = mesh.electrodes[e];
    const double g = 1.0 / z[e];
    const int U = electrode_dof(e);
    if (el.is_point()) {  // the contact impedance lumped at the node
      add(node_dof(el.point_node), node_dof(el.point_node), g);
      add(U, node_dof(el.point_node), -g);
      add(U, U, g);
      continue;
    }
    for (const auto& s : el.segments) {
      const double len = (mesh.nodes.row(s[0]) - mesh.nodes.row(s[1])).norm();
      const int a = node_dof(s[0]), b = node_dof(s[1]);
      add(a, a, g * len / 3);
      add(b, b, g * len / 3);
      add(a, b, g * len / 6);
      add(U, a, -g * len / 2);
      add(U, b, -g * len / 2);
      add(U, U, g * len);
    }
  }
}

void ForwardModel::Impl::analyse() {
  std::vector<double> values = base_values;
  cholmod_sparse A = view(values);
  // Simplicial LDL': on these 2-D meshes it beat the supernodal factor by 1.8x at 13k triangles and
  // tied below (bench/micro), and it keeps BLAS threads out of the result.
  analysis_common.get()->supernodal = CHOLMOD_SIMPLICIAL;
  symbolic = cholmod_analyze(&A, analysis_common.get());
  if (!symbolic || analysis_common.get()->status < CHOLMOD_OK)
    throw std::runtime_error("CHOLMOD could not analyse the system (out of memory?)");
}

cholmod_sparse ForwardModel::Impl::view(std::vector<double>& values) const {
  cholmod_sparse A{};
  A.nrow = A.ncol = static_cast<size_t>(dofs);
  A.nzmax = row_idx.size();
  A.p = const_cast<int*>(col_ptr.data());
  A.i = const_cast<int*>(row_idx.data());
  A.x = values.data();
  A.stype = -1;  // symmetric, lower triangle stored
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

void ForwardOptions::validate() const {
  auto usable = [](double z) { return z > 0 && std::isfinite(z); };
  if (!std::isfinite(current) || current == 0)
    throw InputError("ForwardOptions", "current", "the drive current must be finite and non-zero");
  if (contact_impedances.size() == 0 && !usable(contact_impedance))
    throw InputError("ForwardOptions", "contact_impedance", "must be positive and finite");
  for (Eigen::Index e = 0; e < contact_impedances.size(); ++e)
    if (!usable(contact_impedances[e]))
      throw InputError("ForwardOptions", "contact_impedances",
                       "electrode " + std::to_string(e) + "'s must be positive and finite");
}

ForwardModel::ForwardModel(const Mesh& mesh, const ForwardOptions& options,
                           const std::string& source)
    // The mesh is checked before Impl builds the protocol from its electrode count.
    : impl_((validate_mesh(mesh, source), std::make_unique<Impl>(mesh, options))) {
  options.validate();
  const int L = mesh.num_electrodes();
  if (options.contact_impedances.size() > 0) {
    if (options.contact_impedances.size() != L)
      throw InputError("ForwardOptions", "contact_impedances",
                       "needs one value per electrode (" + std::to_string(L) + ")");
    impl_->z = options.contact_impedances;
  } else {
    impl_->z = Eigen::VectorXd::Constant(L, options.contact_impedance);
  }
  if (impl_->measurement.electrodes() != L)
    throw InputError("ForwardOptions", "protocol",
                     "the " + impl_->measurement.name() + " protocol is for " +
                         std::to_string(impl_->measurement.electrodes()) +
                         " electrodes, the mesh has " + std::to_string(L));
  impl_->build();
  impl_->rhs = Eigen::MatrixXd::Zero(impl_->dofs, L);
  for (int d = 0; d < L; ++d) {
    impl_->rhs(impl_->electrode_dof(d), d) += options.current;
    impl_->rhs(impl_->electrode_dof((d + 1) % L), d) -= options.current;
  }
}

ForwardModel::ForwardModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

ForwardModel ForwardModel::with_contact_impedances(const Eigen::VectorXd& z) const {
  const Impl& from = *impl_;
  const int L = from.mesh.num_electrodes();
  if (z.size() != L)
    throw InputError("ForwardOptions", "contact_impedances",
                     "needs one value per electrode (" + std::to_string(L) + ")");
  ForwardOptions options = from.options;
  options.contact_impedances = z;
  options.validate();
  auto impl = std::make_unique<Impl>(from.mesh, options);
  Impl& to = *impl;
  to.z = z;
  to.dofs = from.dofs;
  to.area = from.area, to.grad = from.grad, to.stiffness = from.stiffness;
  to.scatter = from.scatter, to.col_ptr = from.col_ptr, to.row_idx = from.row_idx;
  to.rhs = from.rhs;
  to.electrode_blocks();  // the one part that depends on z; the pattern does not
  to.symbolic = cholmod_copy_factor(from.symbolic, to.analysis_common.get());
  if (!to.symbolic) throw std::runtime_error("CHOLMOD: out of memory");
  return ForwardModel(std::move(impl));
}

ForwardModel::~ForwardModel() = default;
ForwardModel::ForwardModel(ForwardModel&&) noexcept = default;
ForwardModel& ForwardModel::operator=(ForwardModel&&) noexcept = default;

const Mesh& ForwardModel::mesh() const {
  return impl_->mesh;
}
const Protocol& ForwardModel::protocol() const {
  return impl_->protocol;
}
const MeasurementProtocol& ForwardModel::measurement_protocol() const {
  return impl_->measurement;
}
const ForwardOptions& ForwardModel::options() const {
  return impl_->options;
}

namespace {

// A frame from the electrode potentials U (electrode e, drive d): v = U(m, d) - U(m + 1, d) for
// each measurement pair.
template <typename Potentials>
Eigen::VectorXd adjacent_differences(const std::vector<MeasurementPair>& pairs,
                                     const Potentials& U) {
  const Eigen::Index L = U.rows();
  Eigen::VectorXd v(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const auto [d, m] = pairs[i];
    v[i] = U(m, d) - U((m + 1) % L, d);
  }
  return v;
}

// The voltages of `channels` from the adjacent drives' electrode potentials U (electrode e,
// drive d), each drive pattern's potentials summed from them (drive_patterns.h).
template <typename Potentials>
Eigen::VectorXd channel_voltages(const std::vector<Channel>& channels, const Potentials& U) {
  const detail::DrivePatterns patterns =
      detail::drive_patterns(channels, static_cast<int>(U.rows()));
  const auto W = patterns.combine(U);  // electrode x drive pattern
  Eigen::VectorXd v(channels.size());
  for (std::size_t i = 0; i < channels.size(); ++i) {
    const int d = patterns.drive[i];
    v[i] = W(channels[i].meas_plus, d) - W(channels[i].meas_minus, d);
  }
  return v;
}

// A current-pattern protocol's values from the adjacent drives' electrode potentials U: each
// pattern's potentials summed from them, then every difference under it, pattern-major.
template <typename Potentials>
Eigen::VectorXd pattern_voltages(const CurrentPatterns& patterns, double current,
                                 const Potentials& U) {
  detail::DrivePatterns drives = detail::pattern_drives(patterns, current);
  drives.terms.resize(static_cast<std::size_t>(patterns.patterns()));  // the injections only
  const Eigen::MatrixXd W = drives.combine(U);                         // electrode x pattern
  const Eigen::MatrixXd V = patterns.measurement.transpose() * W;      // difference x pattern
  return Eigen::Map<const Eigen::VectorXd>(V.data(), V.size());        // column-major: p-major
}

}  // namespace

std::unique_ptr<Workspace> ForwardModel::Impl::solve(const Eigen::VectorXd& sigma) const {
  const Impl& m = *this;
  const int T = m.mesh.num_triangles();
  if (sigma.size() != T)
    throw InputError(
        "conductivity", "",
        "has " + std::to_string(sigma.size()) + " values for " + std::to_string(T) + " elements");
  for (int t = 0; t < T; ++t)
    if (!(sigma[t] > 0) || !std::isfinite(sigma[t]))
      throw InputError("conductivity", "element " + std::to_string(t),
                       "must be positive and finite");
  // Each call factorises into a workspace of its own (the factor keeps the symbolic analysis):
  // solve() is safe to call from several threads at once.
  std::unique_ptr<Workspace> w = m.take();
  w->values.assign(m.base_values.begin(), m.base_values.end());
  for (int t = 0; t < T; ++t)
    for (int q = 0; q < kLocalPairs; ++q) {
      const int pos = m.scatter(t, q);
      if (pos >= 0) w->values[pos] += sigma[t] * m.stiffness(t, q);
    }
  cholmod_sparse A = m.view(w->values);
  cholmod_factorize(&A, w->factor, w->common.get());
  if (w->common.get()->status != CHOLMOD_OK) {
    // The workspace may hold a failed factor: drop it rather than pool it.
    if (w->common.get()->status == CHOLMOD_NOT_POSDEF)
      throw NumericalError("CHOLMOD: the CEM system is not positive definite");
    throw std::runtime_error("CHOLMOD: factorisation failed (out of memory?)");
  }
  cholmod_dense B{};
  B.nrow = static_cast<size_t>(m.dofs);
  B.ncol = static_cast<size_t>(m.rhs.cols());
  B.nzmax = B.nrow * B.ncol;
  B.d = B.nrow;
  B.x = const_cast<double*>(m.rhs.data());  // read only
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, w->factor, &B, nullptr, &w->X, nullptr, &w->Y, &w->E,
                      w->common.get()))
    throw std::runtime_error("CHOLMOD: solve failed (out of memory?)");
  // Conductivities near the largest double overflow the assembled system (1.7e308 everywhere gives
  // NaN potentials while CHOLMOD reports success): the numbers, not the input's form, failed.
  const Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>> X(
      static_cast<const double*>(w->X->x), m.dofs, static_cast<Eigen::Index>(w->X->ncol),
      Eigen::OuterStride<>(static_cast<Eigen::Index>(w->X->d)));
  if (!X.allFinite())
    throw NumericalError("the CEM system overflowed: conductivities beyond double precision");
  return w;
}

ForwardSolution ForwardModel::solve(const Eigen::VectorXd& sigma) const {
  const Impl& m = *impl_;
  const int N = m.mesh.num_nodes(), L = m.mesh.num_electrodes();
  std::unique_ptr<Workspace> w = m.solve(sigma);
  const Eigen::Map<const Eigen::MatrixXd> x(static_cast<const double*>(w->X->x), m.dofs, L);
  ForwardSolution solution;
  solution.node_potentials.resize(N, L);
  solution.node_potentials.row(0).setZero();
  solution.node_potentials.bottomRows(N - 1) = x.topRows(N - 1);
  solution.electrode_potentials = x.bottomRows(L);
  m.give_back(std::move(w));
  return solution;
}

Eigen::VectorXd ForwardModel::frame(const ForwardSolution& s, MeasurementOrder order) const {
  return adjacent_differences(impl_->protocol.pairs(order), s.electrode_potentials);
}

Eigen::VectorXd ForwardModel::frame(const Eigen::VectorXd& sigma, MeasurementOrder order) const {
  return impl_->from_electrodes(
      sigma, [&](const auto& U) { return adjacent_differences(impl_->protocol.pairs(order), U); });
}

Eigen::VectorXd ForwardModel::adjacent_map(const ForwardSolution& s) const {
  const int L = impl_->mesh.num_electrodes();
  Eigen::VectorXd v(L * L);
  for (int d = 0; d < L; ++d)
    for (int m = 0; m < L; ++m)
      v[d * L + m] = s.electrode_potentials(m, d) - s.electrode_potentials((m + 1) % L, d);
  return v;
}

Eigen::MatrixXd ForwardModel::electrode_currents(const ForwardSolution& s) const {
  const Impl& m = *impl_;
  const int L = m.mesh.num_electrodes();
  Eigen::MatrixXd current(L, L);
  for (int e = 0; e < L; ++e) {
    const Electrode& el = m.mesh.electrodes[e];
    for (int d = 0; d < L; ++d) {
      const double U = s.electrode_potentials(e, d);
      if (el.is_point()) {
        current(e, d) = (U - s.node_potentials(el.point_node, d)) / m.z[e];
        continue;
      }
      double sum = 0;  // int_e (U - u) / z ds, exact for linear u on each segment
      for (const auto& seg : el.segments) {
        const double len = (m.mesh.nodes.row(seg[0]) - m.mesh.nodes.row(seg[1])).norm();
        sum += len * (U - 0.5 * (s.node_potentials(seg[0], d) + s.node_potentials(seg[1], d)));
      }
      current(e, d) = sum / m.z[e];
    }
  }
  return current;
}

Eigen::MatrixXd ForwardModel::jacobian(const ForwardSolution& s) const {
  return jacobian(s, impl_->protocol.pairs(MeasurementOrder::rotating));
}

Eigen::MatrixXd ForwardModel::jacobian(const ForwardSolution& s,
                                       const std::vector<MeasurementPair>& pairs) const {
  const int L = impl_->mesh.num_electrodes();
  std::vector<Channel> channels;
  channels.reserve(pairs.size());
  for (const auto& [d, m] : pairs) {
    if (d < 0 || d >= L || m < 0 || m >= L)
      throw std::invalid_argument("ForwardModel::jacobian: a pair names no electrode");
    channels.push_back({d, (d + 1) % L, m, (m + 1) % L});
  }
  return jacobian(s, channels);
}

Eigen::MatrixXd ForwardModel::jacobian(const ForwardSolution& s,
                                       const std::vector<Channel>& channels,
                                       const std::vector<int>& elements) const {
  return impl_->jacobian(s, detail::drive_patterns(channels, impl_->mesh.num_electrodes()),
                         elements);
}

Eigen::MatrixXd ForwardModel::Impl::jacobian(const ForwardSolution& s,
                                             const detail::DrivePatterns& patterns,
                                             const std::vector<int>& elements) const {
  const Impl& m = *this;
  const int T = m.mesh.num_triangles(), L = m.mesh.num_electrodes();
  const bool all = elements.empty();
  const int n = all ? T : static_cast<int>(elements.size());
  for (int t : elements)
    if (t < 0 || t >= T) throw std::invalid_argument("ForwardModel::jacobian: no such element");
  // Field gradients per element, all adjacent drives side by side: gx(k, d), gy(k, d).
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> gx(n, L), gy(n, L);
  for (int k = 0; k < n; ++k) {
    const int t = all ? k : elements[static_cast<std::size_t>(k)];
    const auto u0 = s.node_potentials.row(m.mesh.triangles(t, 0));
    const auto u1 = s.node_potentials.row(m.mesh.triangles(t, 1));
    const auto u2 = s.node_potentials.row(m.mesh.triangles(t, 2));
    gx.row(k) = m.grad(t, 0) * u0 + m.grad(t, 1) * u1 + m.grad(t, 2) * u2;
    gy.row(k) = m.grad(t, 3) * u0 + m.grad(t, 4) * u1 + m.grad(t, 5) * u2;
  }
  // The same gradients per drive pattern (an adjacent pattern's column is copied unchanged).
  const auto px = patterns.combine(gx), py = patterns.combine(gy);
  const int rows = static_cast<int>(patterns.drive.size());
  const std::vector<int>&drive = patterns.drive, &measure = patterns.measure;
  Eigen::MatrixXd J(rows, n);
  const double inv_current = 1.0 / m.options.current;
  for (int k = 0; k < n; ++k) {
    const double* x = px.row(k).data();
    const double* y = py.row(k).data();
    const double scale = -m.area[all ? k : elements[static_cast<std::size_t>(k)]] * inv_current;
    double* column = J.col(k).data();
    for (int r = 0; r < rows; ++r)
      column[r] = scale * (x[drive[r]] * x[measure[r]] + y[drive[r]] * y[measure[r]]);
  }
  return J;
}

Eigen::MatrixXd ForwardModel::measured_jacobian(const ForwardSolution& s,
                                                const std::vector<Channel>& channels,
                                                const std::vector<int>& elements) const {
  Eigen::MatrixXd J = jacobian(s, channels, elements);
  if (impl_->measurement.magnitude()) {  // d|v| = sign(v) dv
    const Eigen::VectorXd v = voltages(s, channels);
    for (Eigen::Index r = 0; r < J.rows(); ++r)
      if (v[r] < 0) J.row(r) *= -1.0;
  }
  return J;
}

Eigen::MatrixXd ForwardModel::input_jacobian(const ForwardSolution& s,
                                             const std::vector<int>& elements) const {
  const MeasurementProtocol& p = impl_->measurement;
  if (p.has_patterns())
    return impl_->jacobian(s, detail::pattern_drives(p.patterns(), impl_->options.current),
                           elements);
  return measured_jacobian(s, p.input_channels(), elements);
}

Eigen::VectorXd ForwardModel::voltages(const ForwardSolution& s,
                                       const std::vector<Channel>& channels) const {
  return channel_voltages(channels, s.electrode_potentials);
}

Eigen::VectorXd ForwardModel::measured(const ForwardSolution& s) const {
  const MeasurementProtocol& p = impl_->measurement;
  if (p.has_patterns())
    return pattern_voltages(p.patterns(), impl_->options.current, s.electrode_potentials);
  const Eigen::VectorXd v = voltages(s, p.channels());
  return p.magnitude() ? Eigen::VectorXd(v.cwiseAbs()) : v;
}

Eigen::VectorXd ForwardModel::measured(const Eigen::VectorXd& sigma) const {
  const MeasurementProtocol& p = impl_->measurement;
  const Eigen::VectorXd v = impl_->from_electrodes(sigma, [&](const auto& U) {
    return p.has_patterns() ? pattern_voltages(p.patterns(), impl_->options.current, U)
                            : channel_voltages(p.channels(), U);
  });
  return p.magnitude() ? Eigen::VectorXd(v.cwiseAbs()) : v;
}

Eigen::VectorXd ForwardModel::inputs(const ForwardSolution& s) const {
  const MeasurementProtocol& p = impl_->measurement;
  if (p.has_patterns()) return measured(s);  // every value is an input
  const Eigen::VectorXd v = voltages(s, p.input_channels());
  return p.magnitude() ? Eigen::VectorXd(v.cwiseAbs()) : v;
}

Eigen::VectorXd ForwardModel::inputs(const Eigen::VectorXd& sigma) const {
  return inputs(solve(sigma));
}

Eigen::MatrixXd ForwardModel::jacobian(const Eigen::VectorXd& sigma) const {
  return jacobian(solve(sigma));
}

}  // namespace eitbench
