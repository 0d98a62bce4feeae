#include "eitbench/augment/symmetry.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace {

int wrap(long long i, int L) {
  return static_cast<int>(((i % L) + L) % L);
}
int element_index(const GroupElement& g, int L) {
  return (g.mirror ? L : 0) + g.rotation;
}
int layout_index(FrameLayout layout) {
  return static_cast<int>(layout);
}

// out[i] = frame[table[i]].
Eigen::VectorXd gather(const std::vector<int>& table, const Eigen::VectorXd& frame) {
  if (frame.size() != static_cast<Eigen::Index>(table.size()))
    throw InputError("frame", "values",
                     "has " + std::to_string(frame.size()) + " values, not the layout's " +
                         std::to_string(table.size()));
  Eigen::VectorXd out(frame.size());
  for (std::size_t i = 0; i < table.size(); ++i) out[i] = frame[table[i]];
  return out;
}

}  // namespace

std::string GroupElement::to_string() const {
  return (mirror ? "mirror:" : "rot:") + std::to_string(rotation);
}

GroupElement parse_element(const std::string& text, int L, const std::string& source) {
  const auto colon = text.find(':');
  const std::string kind = text.substr(0, colon);
  if (colon == std::string::npos || (kind != "rot" && kind != "mirror"))
    throw InputError(source, "", "'" + text + "' is not a group element: use rot:S or mirror:S");
  const std::string steps = text.substr(colon + 1);
  errno = 0;
  char* end = nullptr;
  const long long s = std::strtoll(steps.c_str(), &end, 10);
  if (steps.empty() || *end != '\0' || errno == ERANGE)
    throw InputError(source, "", "'" + steps + "' is not a whole number of electrode steps");
  return {wrap(s, L), kind == "mirror"};
}

GroupElement compose(const GroupElement& g, const GroupElement& h, int L) {
  // R(-s1) M^m1 R(-s2) M^m2 = R(-(s1 + (-1)^m1 s2)) M^(m1 xor m2), since M R(a) = R(-a) M.
  return {wrap(g.rotation + (g.mirror ? -h.rotation : h.rotation), L), g.mirror != h.mirror};
}

GroupElement inverse(const GroupElement& g, int L) {
  return g.mirror ? g
                  : GroupElement{wrap(-g.rotation, L), false};  // every mirror is its own inverse
}

AugmentGroup parse_group(const std::string& name, const std::string& source) {
  if (name == "none") return AugmentGroup::none;
  if (name == "rotations") return AugmentGroup::rotations;
  if (name == "mirror") return AugmentGroup::mirror;
  // "group": a sensor's whole symmetry group (D_L on the disk), as "dihedral" is on the disk.
  if (name == "d16" || name == "dihedral" || name == "group") return AugmentGroup::dihedral;
  if (name == "paper") return AugmentGroup::paper;
  throw InputError(source, "",
                   "unknown group '" + name + "' (none, rotations, mirror, d16, group, paper)");
}

std::string to_string(AugmentGroup group) {
  switch (group) {
    case AugmentGroup::none:
      return "none";
    case AugmentGroup::rotations:
      return "rotations";
    case AugmentGroup::mirror:
      return "mirror";
    case AugmentGroup::dihedral:
      return "d16";
    case AugmentGroup::paper:
      return "paper";
  }
  return "?";
}

std::vector<GroupElement> group_elements(AugmentGroup group, int L) {
  std::vector<GroupElement> out{{0, false}};
  if (group == AugmentGroup::rotations || group == AugmentGroup::dihedral ||
      group == AugmentGroup::paper)
    for (int s = 1; s < L; ++s) out.push_back({s, false});
  if (group == AugmentGroup::mirror) out.push_back({0, true});
  if (group == AugmentGroup::dihedral || group == AugmentGroup::paper)
    for (int s = 0; s < L; ++s) out.push_back({s, true});
  return out;
}

int electrode_image(const GroupElement& g, int e, int L) {
  return wrap(g.mirror ? -static_cast<long long>(e) - g.rotation : e - g.rotation, L);
}

Eigen::Vector2d transform_point(const Eigen::Vector2d& p, const GroupElement& g, int L) {
  const double y = g.mirror ? -p.y() : p.y();
  const double a = -2 * M_PI * g.rotation / L;
  const double c = std::cos(a), s = std::sin(a);
  return {c * p.x() - s * y, s * p.x() + c * y};
}

std::vector<Circle> transform_circles(const std::vector<Circle>& circles, const GroupElement& g,
                                      int L) {
  std::vector<Circle> out = circles;
  for (Circle& c : out) {
    const Eigen::Vector2d p = transform_point({c.x, c.y}, g, L);
    c.x = p.x();
    c.y = p.y();
  }
  return out;
}

FrameSymmetry::FrameSymmetry(int L) : protocol_(L) {
  const Protocol& p = protocol_;
  for (auto layout : {FrameLayout::rotating, FrameLayout::ascending, FrameLayout::reduced}) {
    auto& table = permutations_[layout_index(layout)];
    table.resize(2 * L);
    for (int index = 0; index < 2 * L; ++index) {
      const GroupElement g{index % L, index >= L};
      auto map = [&](int i) {
        return g.mirror ? wrap(-(i + g.rotation) - 1, L) : wrap(i + g.rotation, L);
      };
      auto& perm = table[index];
      if (layout == FrameLayout::reduced) {
        for (const auto& [d, m] : p.reduced_pairs())
          perm.push_back(
              p.rotating_to_reduced()[p.index(map(d), map(m), MeasurementOrder::rotating)]);
      } else {
        const MeasurementOrder order = layout == FrameLayout::rotating
                                           ? MeasurementOrder::rotating
                                           : MeasurementOrder::ascending;
        for (const auto& [d, m] : p.pairs(order)) perm.push_back(p.index(map(d), map(m), order));
      }
    }
    // The paper's Algorithms move whole values too: run them once on the frame of indices.
    const Eigen::Index size = static_cast<Eigen::Index>(table[0].size());
    const Eigen::VectorXd indices = Eigen::VectorXd::LinSpaced(size, 0, double(size - 1));
    auto& paper = paper_permutations_[layout_index(layout)];
    for (int index = 0; index < 2 * L; ++index) {
      const Eigen::VectorXd moved = paper_algorithm({index % L, index >= L}, indices, p, layout);
      paper.emplace_back(moved.begin(), moved.end());  // exact: small integers in doubles
    }
  }
}

const std::vector<int>& FrameSymmetry::permutation(const GroupElement& g,
                                                   FrameLayout layout) const {
  return permutations_[layout_index(layout)][element_index(g, electrodes())];
}

Eigen::VectorXd FrameSymmetry::apply(const GroupElement& g, const Eigen::VectorXd& frame,
                                     FrameLayout layout) const {
  return gather(permutation(g, layout), frame);
}

Eigen::VectorXd paper_algorithm(const GroupElement& g, const Eigen::VectorXd& frame,
                                const Protocol& protocol, FrameLayout layout) {
  const int L = protocol.electrodes();
  Eigen::MatrixXd map = impedance_map(frame, protocol, layout);
  if (g.mirror) map = map.rowwise().reverse().eval();  // Algorithm 2: reverse each row's columns
  Eigen::MatrixXd shifted(map.rows(), map.cols());     // Algorithm 1: row d <- row d + s
  for (int d = 0; d < L; ++d) shifted.row(d) = map.row(wrap(d + g.rotation, L));
  return frame_from_map(shifted, protocol, layout);
}

Eigen::VectorXd FrameSymmetry::apply_paper(const GroupElement& g, const Eigen::VectorXd& frame,
                                           FrameLayout layout) const {
  return gather(paper_permutation(g, layout), frame);
}

const std::vector<int>& FrameSymmetry::paper_permutation(const GroupElement& g,
                                                         FrameLayout layout) const {
  return paper_permutations_[layout_index(layout)][element_index(g, electrodes())];
}

Eigen::VectorXd FrameSymmetry::apply(AugmentGroup group, const GroupElement& g,
                                     const Eigen::VectorXd& frame, FrameLayout layout) const {
  return group == AugmentGroup::paper ? apply_paper(g, frame, layout) : apply(g, frame, layout);
}

const std::vector<int>& FrameSymmetry::table(AugmentGroup group, const GroupElement& g,
                                             FrameLayout layout) const {
  return group == AugmentGroup::paper ? paper_permutation(g, layout) : permutation(g, layout);
}

}  // namespace eitbench
