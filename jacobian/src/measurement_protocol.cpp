#include "eitbench/jacobian/measurement_protocol.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/read_budget.h"

namespace eitbench {
namespace {

using Key = std::array<int, 4>;
Key key(const Channel& c) {
  return {c.drive_plus, c.drive_minus, c.meas_plus, c.meas_minus};
}

// The channel's problem, or "" when it is fine for L electrodes.
std::string channel_problem(const Channel& c, int L) {
  for (int e : key(c))
    if (e < 0 || e >= L)
      return "electrode " + std::to_string(e) + " is outside 0.." + std::to_string(L - 1);
  if (c.drive_plus == c.drive_minus)
    return "drive+ equals drive- (" + std::to_string(c.drive_plus) + ")";
  if (c.meas_plus == c.meas_minus)
    return "meas+ equals meas- (" + std::to_string(c.meas_plus) + ")";
  return "";
}

// Four comma-separated integers (a header line is not).
bool looks_like_channel(const std::string& line) {
  std::stringstream cells(line);
  std::string cell;
  int count = 0;
  while (std::getline(cells, cell, ',')) {
    char* end = nullptr;
    std::strtol(cell.c_str(), &end, 10);
    while (*end == ' ' || *end == '\t') ++end;
    if (end == cell.c_str() || *end != '\0') return false;
    ++count;
  }
  return count == 4;
}

int wrap(int i, int L) {
  return ((i % L) + L) % L;
}

}  // namespace

MeasurementProtocol::MeasurementProtocol(std::string name, int electrodes,
                                         std::vector<Channel> channels, const std::string& source)
    : name_(std::move(name)), electrodes_(electrodes), channels_(std::move(channels)) {
  if (electrodes_ < 2)
    throw InputError(source, "electrodes",
                     "a protocol needs at least 2 electrodes, got " + std::to_string(electrodes_));
  if (channels_.empty()) throw InputError(source, "channels", "the protocol has no channel");
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const std::string field = "channel " + std::to_string(i);
    const std::string problem = channel_problem(channels_[i], electrodes_);
    if (!problem.empty()) throw InputError(source, field, problem);
    const auto [it, fresh] = index_.emplace(key(channels_[i]), static_cast<int>(i));
    if (!fresh) throw InputError(source, field, "repeats channel " + std::to_string(it->second));
  }
  // Reciprocal when every channel's reciprocal is listed; the inputs then keep the first of each.
  std::vector<int> partner(channels_.size(), -1);
  reciprocal_ = true;
  for (std::size_t i = 0; i < channels_.size() && reciprocal_; ++i) {
    const Channel& c = channels_[i];
    partner[i] = find({c.meas_plus, c.meas_minus, c.drive_plus, c.drive_minus});
    reciprocal_ = partner[i] >= 0;
  }
  for (std::size_t i = 0; i < channels_.size(); ++i)
    if (!reciprocal_ || partner[i] >= static_cast<int>(i)) inputs_.push_back(static_cast<int>(i));
}

MeasurementProtocol::MeasurementProtocol(std::string name, CurrentPatterns patterns,
                                         const std::string& source)
    : name_(std::move(name)), electrodes_(0) {
  patterns.validate(source);
  electrodes_ = patterns.electrodes();
  inputs_.resize(static_cast<std::size_t>(patterns.size()));
  for (int i = 0; i < patterns.size(); ++i) inputs_[static_cast<std::size_t>(i)] = i;
  patterns_.push_back(std::move(patterns));
}

int MeasurementProtocol::size() const {
  return has_patterns() ? patterns_.front().size() : static_cast<int>(channels_.size());
}

const CurrentPatterns& MeasurementProtocol::patterns() const {
  if (!has_patterns())
    throw std::logic_error("MeasurementProtocol::patterns: '" + name_ +
                           "' is a protocol of channels");
  return patterns_.front();
}

MeasurementProtocol MeasurementProtocol::with_magnitude(bool magnitude) const {
  if (magnitude && has_patterns())
    throw InputError("protocol", "magnitude",
                     "'" + name_ + "' is given by current patterns, whose values are signed");
  MeasurementProtocol out = *this;
  out.magnitude_ = magnitude;
  return out;
}

std::vector<Channel> MeasurementProtocol::input_channels() const {
  if (has_patterns())
    throw std::logic_error("MeasurementProtocol::input_channels: '" + name_ +
                           "' is given by current patterns, not channels");
  std::vector<Channel> out;
  out.reserve(inputs_.size());
  for (int i : inputs_) out.push_back(channels_[i]);
  return out;
}

Eigen::VectorXd MeasurementProtocol::to_inputs(const Eigen::VectorXd& frame) const {
  if (frame.size() != size())
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the " + name_ +
                         " protocol's " + std::to_string(size()));
  Eigen::VectorXd out(input_size());
  for (int i = 0; i < input_size(); ++i) out[i] = frame[inputs_[i]];
  return out;
}

int MeasurementProtocol::find(const Channel& c, int* sign) const {
  // Exact first; then one pair reversed (the value negated); then both (the value kept).
  const std::array<std::pair<Channel, int>, 4> candidates{{
      {c, 1},
      {{c.drive_plus, c.drive_minus, c.meas_minus, c.meas_plus}, -1},
      {{c.drive_minus, c.drive_plus, c.meas_plus, c.meas_minus}, -1},
      {{c.drive_minus, c.drive_plus, c.meas_minus, c.meas_plus}, 1},
  }};
  for (const auto& [candidate, s] : candidates) {
    const auto it = index_.find(key(candidate));
    if (it == index_.end()) continue;
    if (sign) *sign = s;
    return it->second;
  }
  return -1;
}

bool MeasurementProtocol::same_channels(const MeasurementProtocol& o) const {
  return electrodes_ == o.electrodes_ && channels_ == o.channels_ && patterns_ == o.patterns_ &&
         magnitude_ == o.magnitude_;
}

std::string MeasurementProtocol::csv() const {
  if (has_patterns())
    throw std::logic_error("MeasurementProtocol::csv: '" + name_ +
                           "' is given by current patterns, which have no CSV form");
  std::ostringstream out;
  out << "drive+,drive-,meas+,meas-\n";
  for (const Channel& c : channels_)
    out << c.drive_plus << ',' << c.drive_minus << ',' << c.meas_plus << ',' << c.meas_minus
        << '\n';
  return out.str();
}

MeasurementProtocol adjacent_protocol(int electrodes, MeasurementOrder order) {
  const Protocol adjacent(electrodes);
  const int L = electrodes;
  std::vector<Channel> channels;
  for (const auto& [d, m] : adjacent.pairs(order))
    channels.push_back({d, wrap(d + 1, L), m, wrap(m + 1, L)});
  return MeasurementProtocol(
      order == MeasurementOrder::rotating ? "adjacent" : "adjacent-ascending", L,
      std::move(channels));
}

bool is_adjacent(const MeasurementProtocol& p) {
  return p.electrodes() >= 4 && !p.magnitude() &&
         (p.same_channels(adjacent_protocol(p.electrodes(), MeasurementOrder::rotating)) ||
          p.same_channels(adjacent_protocol(p.electrodes(), MeasurementOrder::ascending)));
}

MeasurementProtocol skip_protocol(int electrodes, int skip) {
  const int L = electrodes;
  if (L < 4)
    throw InputError("protocol", "electrodes",
                     "a skip protocol needs at least 4 electrodes, got " + std::to_string(L));
  if (skip < 0 || skip > L - 2)
    throw InputError("protocol", "skip",
                     "skip-" + std::to_string(skip) + " needs 0 <= K <= " + std::to_string(L - 2) +
                         " for " + std::to_string(L) + " electrodes");
  std::vector<Channel> channels;
  for (int e = 0; e < L; ++e) {
    const int a = e, b = wrap(e + skip + 1, L);
    for (int k = 0; k < L; ++k) {
      const int n = wrap(k + 1, L);
      if (k == a || k == b || n == a || n == b) continue;
      channels.push_back({a, b, n, k});
    }
  }
  return MeasurementProtocol("skip-" + std::to_string(skip), L, std::move(channels));
}

MeasurementProtocol opposite_protocol(int electrodes) {
  if (electrodes < 4 || electrodes % 2 != 0)
    throw InputError("protocol", "electrodes",
                     "the opposite protocol needs an even number of electrodes (at least 4), got " +
                         std::to_string(electrodes));
  const MeasurementProtocol skip = skip_protocol(electrodes, electrodes / 2 - 1);
  return MeasurementProtocol("opposite", electrodes, skip.channels());
}

MeasurementProtocol parse_protocol_csv(const std::string& text, int electrodes,
                                       const std::string& name, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  std::vector<Channel> channels;
  std::map<Key, int> seen;  // channel -> its line
  bool first = true;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    // The first line names the columns; one that is already a channel (a file written without a
    // header, as MATLAB's writematrix does) is read as one rather than dropped.
    if (std::exchange(first, false) && !looks_like_channel(line)) continue;
    const std::string field = "line " + std::to_string(number);
    std::vector<int> values;
    std::stringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) {
      const auto first = cell.find_first_not_of(" \t"), last = cell.find_last_not_of(" \t");
      const std::string trimmed =
          first == std::string::npos ? "" : cell.substr(first, last - first + 1);
      errno = 0;
      char* end = nullptr;
      const long v = std::strtol(trimmed.c_str(), &end, 10);
      if (trimmed.empty() || *end != '\0' || errno == ERANGE || v < -1000000 || v > 1000000)
        throw InputError(source, field, "'" + trimmed + "' is not an integer electrode index");
      values.push_back(static_cast<int>(v));
    }
    if (values.size() != 4)
      throw InputError(source, field,
                       "has " + std::to_string(values.size()) +
                           " columns; a channel is drive+,drive-,meas+,meas-");
    const Channel c{values[0], values[1], values[2], values[3]};
    const std::string problem = channel_problem(c, electrodes);
    if (!problem.empty()) throw InputError(source, field, problem);
    const auto [it, fresh] = seen.emplace(key(c), number);
    if (!fresh)
      throw InputError(source, field, "repeats the channel of line " + std::to_string(it->second));
    channels.push_back(c);
  }
  if (channels.empty())
    throw InputError(source, "", "no channel: a header line, then drive+,drive-,meas+,meas- lines");
  return MeasurementProtocol(name, electrodes, std::move(channels), source);
}

MeasurementProtocol read_protocol_csv(const std::string& path, int electrodes) {
  require_input_file(path);
  std::ifstream in(path, std::ios::binary);
  in.seekg(0, std::ios::end);
  const auto bytes = static_cast<std::uint64_t>(in.tellg());
  if (bytes > read_limit_bytes())
    throw InputError(path, "", "is " + byte_size_text(double(bytes)) + ", over the read limit");
  in.seekg(0);
  std::ostringstream text;
  text << in.rdbuf();
  const auto slash = path.find_last_of('/');
  return parse_protocol_csv(text.str(), electrodes,
                            slash == std::string::npos ? path : path.substr(slash + 1), path);
}

MeasurementProtocol make_protocol(const std::string& spec, int electrodes,
                                  const std::string& source) {
  if (spec == "adjacent") return adjacent_protocol(electrodes, MeasurementOrder::rotating);
  if (spec == "adjacent-ascending")
    return adjacent_protocol(electrodes, MeasurementOrder::ascending);
  if (spec == "opposite") return opposite_protocol(electrodes);
  if (spec.rfind("skip-", 0) == 0) {
    const std::string k = spec.substr(5);
    char* end = nullptr;
    errno = 0;
    const long K = std::strtol(k.c_str(), &end, 10);
    if (k.empty() || *end != '\0' || errno == ERANGE || K < 0 || K > 1000000)
      throw InputError(source, "", "'" + spec + "': skip-K needs a whole number K >= 0");
    return skip_protocol(electrodes, static_cast<int>(K));
  }
  if (spec.size() > 4 && spec.substr(spec.size() - 4) == ".csv")
    return read_protocol_csv(spec, electrodes);
  throw InputError(source, "",
                   "unknown protocol '" + spec +
                       "' (adjacent, adjacent-ascending, opposite, skip-K, or a FILE.csv)");
}

std::vector<int> weak_channels(const Eigen::VectorXd& v0, double tolerance) {
  std::vector<int> out;
  const double scale = v0.size() ? v0.cwiseAbs().maxCoeff() : 0.0;
  for (Eigen::Index i = 0; i < v0.size(); ++i)
    if (std::abs(v0[i]) < tolerance * scale) out.push_back(static_cast<int>(i));
  return out;
}

}  // namespace eitbench
