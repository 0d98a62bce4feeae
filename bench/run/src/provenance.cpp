#include "provenance.h"

#include <fmt/core.h>

#include "eitbench/bench/io/content_hash.h"

namespace eitbench::run {

std::string fingerprint(const Provenance& p) {
  Hasher h;
  for (const auto& [key, value] : p) h.add(key), h.add(value);
  return h.hex();
}

std::string differing_parts(const Provenance& stored, const Provenance& wanted) {
  std::vector<std::string> parts;
  for (const auto& [key, value] : wanted) {
    const auto it = stored.find(key);
    if (it == stored.end() || it->second != value) parts.push_back(key);
  }
  for (const auto& [key, value] : stored)
    if (!wanted.count(key)) parts.push_back(key);
  std::string text;
  for (const std::string& p : parts) text += (text.empty() ? "" : ", ") + p;
  return text;
}

std::string content_hash(const Dataset& d) {
  Hasher h;
  h.add(static_cast<std::uint64_t>(d.electrodes)), h.add(d.radius), h.add(d.background);
  h.add(d.contact_impedance), h.add(d.current), h.add(d.electrode_coverage);
  h.add(static_cast<std::uint64_t>(d.image_size));
  h.add_matrix(d.reference), h.add_matrix(d.frames), h.add_matrix(d.differences);
  h.add_matrix(d.labels);
  h.add(static_cast<std::uint64_t>(d.circles.size()));
  for (const auto& list : d.circles) {
    h.add(static_cast<std::uint64_t>(list.size()));
    for (const Circle& c : list) h.add(c.x), h.add(c.y), h.add(c.r), h.add(c.conductivity);
  }
  for (Split s : d.split) h.add(static_cast<std::uint64_t>(s));
  // A sensor of another shape: its mesh too (a disk's hash stays what it was).
  if (!d.sensor_mesh.empty()) h.add(d.sensor_mesh);
  return h.hex();
}

}  // namespace eitbench::run
