#pragma once
// A measurement protocol as data: the list of channels a board reads, each a current drive and a
// voltage measurement between two pairs of electrodes (docs/protocols.md), or current patterns
// (current_patterns.h: any currents through any electrodes, as KTC2023 drives its tank). Protocol
// (protocol.h) is the adjacent one's index arithmetic; this is any protocol, the adjacent one
// included, and what the forward model, the Jacobian, the augmentation, data sets and model files
// follow.
#include <Eigen/Core>
#include <array>
#include <map>
#include <string>
#include <vector>

#include "eitbench/jacobian/current_patterns.h"
#include "eitbench/jacobian/protocol.h"

namespace eitbench {

// Current +I into drive_plus and out of drive_minus; v = U(meas_plus) - U(meas_minus).
// Electrodes are 0-based.
struct Channel {
  int drive_plus = 0, drive_minus = 1, meas_plus = 2, meas_minus = 3;
  bool operator==(const Channel& o) const {
    return drive_plus == o.drive_plus && drive_minus == o.drive_minus && meas_plus == o.meas_plus &&
           meas_minus == o.meas_minus;
  }
};

class MeasurementProtocol {
 public:
  // Checks every channel (InputError(source, "channel N") for an electrode outside 0..L-1,
  // drive+ equal to drive-, meas+ equal to meas-, or a channel listed twice). `name` is what
  // reports, data sets and model files print: adjacent, opposite, skip-K or the CSV's file name.
  MeasurementProtocol(std::string name, int electrodes, std::vector<Channel> channels,
                      const std::string& source = "protocol");
  // A protocol of current patterns (patterns.validate(source) first): patterns.size() values,
  // every one an input; no channels, not reciprocal, never magnitudes.
  MeasurementProtocol(std::string name, CurrentPatterns patterns,
                      const std::string& source = "protocol");

  const std::string& name() const { return name_; }
  int electrodes() const { return electrodes_; }
  int size() const;
  // The four-electrode channels; empty for a protocol of current patterns.
  const std::vector<Channel>& channels() const { return channels_; }
  // Whether the protocol is given by current patterns, and those patterns (std::logic_error for a
  // protocol of channels).
  bool has_patterns() const { return !patterns_.empty(); }
  const CurrentPatterns& patterns() const;

  // Boards such as OpenEIT report |v|: frames are magnitudes, and the model's frames and
  // Jacobian are those of |v| (ForwardModel). False by default; with_magnitude(true) is an
  // InputError for current patterns.
  bool magnitude() const { return magnitude_; }
  MeasurementProtocol with_magnitude(bool magnitude) const;

  // Reciprocal: every channel's reciprocal (drive and measurement pairs exchanged, in either
  // orientation) is in the protocol, so half the values are redundant.
  bool reciprocal() const { return reciprocal_; }
  // The independent values a reconstructor takes: for a reciprocal protocol the first channel of
  // each reciprocal pair, in protocol order (for the adjacent protocol the reduced 104 of
  // docs/conventions.md, in their order); otherwise every channel.
  const std::vector<int>& inputs() const { return inputs_; }
  int input_size() const { return static_cast<int>(inputs_.size()); }
  std::vector<Channel> input_channels() const;  // std::logic_error for current patterns
  // The inputs of a frame of size() values (InputError("frame", "values") for another size).
  Eigen::VectorXd to_inputs(const Eigen::VectorXd& frame) const;

  // The channel whose four electrodes are c's, with either pair's orientation reversed: its index
  // and the sign its value has relative to c's (-1 for one reversal), preferring an exact match.
  // -1 when the protocol has none.
  int find(const Channel& c, int* sign = nullptr) const;

  // Same channels (or current patterns) in the same order, same magnitude flag (the name is a
  // label).
  bool same_channels(const MeasurementProtocol& o) const;
  // The CSV form (header, then drive+,drive-,meas+,meas- a line) that read_protocol_csv reads.
  // Channels only: std::logic_error for current patterns, which have no such form.
  std::string csv() const;

 private:
  std::string name_;
  int electrodes_;
  std::vector<Channel> channels_;
  std::vector<CurrentPatterns> patterns_;  // one, or none for a protocol of channels
  bool magnitude_ = false;
  bool reciprocal_ = false;
  std::vector<int> inputs_;
  std::map<std::array<int, 4>, int> index_;  // channel electrodes -> position
};

// The adjacent protocol, channel (d, d+1, m, m+1) for Protocol's pairs in `order`: L(L-3)
// channels, reciprocal, L(L-3)/2 inputs (the reduced layout).
MeasurementProtocol adjacent_protocol(int electrodes,
                                      MeasurementOrder order = MeasurementOrder::rotating);
// True when `p` has the adjacent protocol's channels (either order), whatever its name: its inputs
// are then the reduced layout, on which the adjacent-only tools (the paper's map) work.
bool is_adjacent(const MeasurementProtocol& p);
// Drive e -> e + K + 1 for e = 0..L-1; measurement (k+1, k) for k = 0..L-1 ascending, the pairs
// that touch a drive electrode skipped: pyEIT's protocol.create(L, dist_exc=K+1, step_meas=1,
// parser_meas='std') row for row. 0 <= K <= L-2 (InputError("protocol", "skip") otherwise).
MeasurementProtocol skip_protocol(int electrodes, int skip);
// skip-(L/2 - 1), L even: drive e -> e + L/2. For 16 electrodes the 192 channels of OpenEIT's
// lookup table, in its order.
MeasurementProtocol opposite_protocol(int electrodes);

// A protocol from CSV text: a header line (optional: a first line of four integers is a channel),
// then one channel a line as four integers (drive+, drive-, meas+, meas-); blank lines skipped.
// InputError(source, "line N") names the line of a non-integer, a wrong column count, an electrode
// out of range, a pair of one electrode, or a duplicate channel.
MeasurementProtocol parse_protocol_csv(const std::string& text, int electrodes,
                                       const std::string& name, const std::string& source);
MeasurementProtocol read_protocol_csv(const std::string& path, int electrodes);

// By name: adjacent (rotating order), adjacent-ascending, opposite, skip-K, or a path ending in
// .csv. InputError(source, "") for anything else.
MeasurementProtocol make_protocol(const std::string& spec, int electrodes,
                                  const std::string& source = "--protocol");

// Channels whose homogeneous value is weak: |v0_i| < tolerance * max |v0| (the magnitude's sign,
// and so its derivative, is unreliable there). Indices into v0.
std::vector<int> weak_channels(const Eigen::VectorXd& v0, double tolerance = 1e-3);

}  // namespace eitbench
