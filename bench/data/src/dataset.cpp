#include "eitbench/bench/data/dataset.h"

namespace eitbench {

std::string to_string(Split split) {
  switch (split) {
    case Split::train:
      return "train";
    case Split::validation:
      return "validation";
    case Split::test:
      return "test";
  }
  return "?";
}

std::vector<int> Dataset::indices(Split which) const {
  std::vector<int> out;
  for (std::size_t i = 0; i < split.size(); ++i)
    if (split[i] == which) out.push_back(static_cast<int>(i));
  return out;
}

MeasurementProtocol measurement_protocol(const Dataset& d) {
  if (d.protocol_channels.empty())
    return adjacent_protocol(d.electrodes).with_magnitude(d.magnitude);
  return MeasurementProtocol(d.protocol, d.electrodes, d.protocol_channels, "protocol")
      .with_magnitude(d.magnitude);
}

void set_protocol(Dataset& d, const MeasurementProtocol& p) {
  d.protocol = p.name();
  d.protocol_channels = p.channels();
  d.magnitude = p.magnitude();
}

}  // namespace eitbench
