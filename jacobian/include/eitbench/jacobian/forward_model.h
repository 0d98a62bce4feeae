#pragma once
// The complete electrode model (CEM) on linear triangles with one conductivity per element, solved
// by sparse Cholesky (SuiteSparse CHOLMOD through Eigen). The symbolic analysis is done once per
// mesh; each conductivity costs one assembly, one numeric factorisation, and L solves that share
// it.
#include <Eigen/Core>
#include <memory>

#include "eitbench/jacobian/measurement_protocol.h"
#include "eitbench/jacobian/mesh.h"
#include "eitbench/jacobian/protocol.h"

namespace eitbench {

struct ForwardOptions {
  double current = 1.0;  // I, the drive amplitude (A): finite and non-zero
  // z_c for every electrode (Ohm m; lumped Ohm for point ones): positive and finite.
  double contact_impedance = 0.01;
  // One z_c per electrode (each positive and finite); overrides contact_impedance when non-empty.
  Eigen::VectorXd contact_impedances{};
  // The channels frames are read on (docs/protocols.md); null: the adjacent protocol in rotating
  // order. Its electrode count must be the mesh's.
  std::shared_ptr<const MeasurementProtocol> protocol{};

  // Throws InputError("ForwardOptions", field) for a value out of range; whether
  // contact_impedances has one value per electrode is checked against the mesh by ForwardModel.
  void validate() const;
};

// The fields of all L adjacent drives for one conductivity.
struct ForwardSolution {
  Eigen::MatrixXd node_potentials;       // nodes x L; column d is drive d
  Eigen::MatrixXd electrode_potentials;  // L x L; (e, d): electrode e under drive d
};

class ForwardModel {
 public:
  // Validates the mesh and the options (InputError, source `source`) and analyses the pattern.
  ForwardModel(const Mesh& mesh, const ForwardOptions& options = {},
               const std::string& source = "mesh");
  ~ForwardModel();
  ForwardModel(ForwardModel&&) noexcept;
  ForwardModel& operator=(ForwardModel&&) noexcept;

  const Mesh& mesh() const;
  const Protocol& protocol() const;  // the adjacent protocol's index arithmetic
  // The protocol frames follow: ForwardOptions::protocol, or the adjacent one.
  const MeasurementProtocol& measurement_protocol() const;
  const ForwardOptions& options() const;

  // This model with other contact impedances (one an electrode, each positive and finite:
  // InputError otherwise): the same frames as a ForwardModel built with them, bit for bit,
  // without checking the mesh or analysing the pattern again. A calibration builds one a
  // parameter of every Jacobian it takes.
  ForwardModel with_contact_impedances(const Eigen::VectorXd& contact_impedances) const;

  // Solves all drives; sigma has one positive, finite value per triangle (InputError otherwise).
  ForwardSolution solve(const Eigen::VectorXd& sigma) const;

  // The measured voltages of a solution in the given order (L(L-3) values).
  Eigen::VectorXd frame(const ForwardSolution& solution,
                        MeasurementOrder order = MeasurementOrder::rotating) const;
  Eigen::VectorXd frame(const Eigen::VectorXd& sigma,
                        MeasurementOrder order = MeasurementOrder::rotating) const;

  // Any protocol's frames come from the same L adjacent solves (see drive_patterns.h).
  // The signed voltages of `channels`.
  Eigen::VectorXd voltages(const ForwardSolution& solution,
                           const std::vector<Channel>& channels) const;
  // What a board on measurement_protocol() reports: every channel, |v| for a magnitude protocol;
  // for current patterns every difference under every pattern, pattern-major (the patterns'
  // currents in the unit of ForwardOptions::current, which then only sets the drives solved).
  Eigen::VectorXd measured(const ForwardSolution& solution) const;
  Eigen::VectorXd measured(const Eigen::VectorXd& sigma) const;  // reads electrode rows only
  // The protocol's inputs (the values reconstructors take), |v| for a magnitude protocol.
  Eigen::VectorXd inputs(const ForwardSolution& solution) const;
  Eigen::VectorXd inputs(const Eigen::VectorXd& sigma) const;

  // Every adjacent pair under every drive, the three that touch a driven electrode included:
  // L x L values, v(d, m) = U_m - U_{m+1} at d * L + m (the layout import reads as an L x L map).
  // Only these see the contact impedances strongly: a driven electrode's potential carries z I/|e|.
  Eigen::VectorXd adjacent_map(const ForwardSolution& solution) const;

  // Net current through each electrode (L x L, column d for drive d), from the CEM's boundary
  // terms.
  Eigen::MatrixXd electrode_currents(const ForwardSolution& solution) const;

  // d v / d sigma_k on elements by the adjoint method: rows in rotating order (L(L-3) rows), one
  // column per triangle. The adjoint of measurement m is drive m's field scaled by 1/I, so the
  // drive solves give every row: J(d,m; k) = -area_k * grad u_d . grad u_m / I.
  Eigen::MatrixXd jacobian(const ForwardSolution& solution) const;
  // Only the rows of `pairs` (e.g. protocol().reduced_pairs(), the 104 a reconstruction uses):
  // each row costs as much as any other, so asking for fewer is that much faster.
  Eigen::MatrixXd jacobian(const ForwardSolution& solution,
                           const std::vector<MeasurementPair>& pairs) const;
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& sigma) const;
  // Rows for any channels (signed voltages): J = -area * grad u_drive . grad u_meas / I, with
  // each field the sum of adjacent drives' fields. With `elements`, only their columns, in that
  // order (each column costs as much as any other: a model that moves few elements asks for
  // those); empty: every triangle's.
  Eigen::MatrixXd jacobian(const ForwardSolution& solution, const std::vector<Channel>& channels,
                           const std::vector<int>& elements = {}) const;
  // Rows of `channels` as the protocol reports them: for a magnitude protocol d|v| = sign(v) dv,
  // the sign at this solution.
  Eigen::MatrixXd measured_jacobian(const ForwardSolution& solution,
                                    const std::vector<Channel>& channels,
                                    const std::vector<int>& elements = {}) const;
  // The inputs' rows (measured_jacobian of the protocol's input channels, or every value of a
  // protocol of current patterns), of every triangle or of `elements` only.
  Eigen::MatrixXd input_jacobian(const ForwardSolution& solution,
                                 const std::vector<int>& elements = {}) const;

 private:
  struct Impl;
  explicit ForwardModel(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace eitbench
