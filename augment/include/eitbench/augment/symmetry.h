#pragma once
// The sensor's symmetry group D_L acting on frames, points and circles (docs/conventions.md).
//
// An element g = (s, mirror) means: mirror first (theta -> -theta, electrode e -> -e), then
// rotate by s electrode steps. On frames, v'(d, m) = v(p(d), p(m)) with p(i) = i + s, or
// p(i) = -(i + s) - 1 after the mirror. On the touch, g moves a point x to R(-2 pi s / L) M x: the
// frame v'(d, m) = v(d+s, m+s) is that of the touch turned by -s electrode steps.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "eitbench/augment/impedance_map.h"
#include "eitbench/jacobian/geometry.h"
#include "eitbench/jacobian/protocol.h"

namespace eitbench {

struct GroupElement {
  int rotation = 0;     // s in 0 .. L-1
  bool mirror = false;  // applied before the rotation

  bool operator==(const GroupElement& o) const {
    return rotation == o.rotation && mirror == o.mirror;
  }
  bool operator!=(const GroupElement& o) const { return !(*this == o); }
  std::string to_string() const;  // "rot:S" or "mirror:S"
};

// "rot:S" (rotation by S electrode steps) or "mirror:S" (the mirror, then rot:S); S any integer,
// taken mod L. Throws InputError naming `source`.
GroupElement parse_element(const std::string& text, int electrodes,
                           const std::string& source = "GroupElement");
GroupElement compose(const GroupElement& g, const GroupElement& h, int electrodes);  // g after h
GroupElement inverse(const GroupElement& g, int electrodes);

enum class AugmentGroup {
  none,       // the frame itself
  rotations,  // the L rotations
  mirror,     // identity and the mirror through electrode 0
  dihedral,   // D_L: L rotations x {identity, mirror}, 2L elements ("d16" for L = 16)
  paper,      // the paper's literal Algorithms 1 + 2: rotations, and its column-reversal "mirror"
};
// none | rotations | mirror | d16 | dihedral | paper (d16 names D_L for any L).
AugmentGroup parse_group(const std::string& name, const std::string& source = "AugmentGroup");
std::string to_string(AugmentGroup group);
// The elements, identity first: rotations s = 0..L-1, then mirror:0..L-1 where the group has them.
std::vector<GroupElement> group_elements(AugmentGroup group, int electrodes);

// The electrode g moves electrode e onto (on the disk, where transform_point takes its centre):
// e - S for rot:S, -e - S for mirror:S, mod L.
int electrode_image(const GroupElement& g, int electrode, int electrodes);
// Where g moves a point of the touch, and the circles of a parametric touch.
Eigen::Vector2d transform_point(const Eigen::Vector2d& p, const GroupElement& g, int electrodes);
std::vector<Circle> transform_circles(const std::vector<Circle>& circles, const GroupElement& g,
                                      int electrodes);

// Frame actions, precomputed as index permutations for every element and layout.
class FrameSymmetry {
 public:
  explicit FrameSymmetry(int electrodes);
  int electrodes() const { return protocol_.electrodes(); }
  const Protocol& protocol() const { return protocol_; }

  // out[i] = in[permutation[i]] for a frame in `layout`.
  const std::vector<int>& permutation(const GroupElement& g, FrameLayout layout) const;
  // The frame of the touch g moves. Throws InputError("frame", "values") for a frame of the
  // wrong size (a frame is data).
  Eigen::VectorXd apply(const GroupElement& g, const Eigen::VectorXd& frame,
                        FrameLayout layout) const;
  // The paper's variant: Algorithm 1 (a circular shift of the map's rows by s), after Algorithm 2
  // (each row's columns reversed, the row order kept) when g has the mirror. Algorithm 2 is not a
  // mirror: row d alone equals the mirror about the gap between electrodes d and d+1, so every row
  // is mirrored about another axis, and the result breaks reciprocity. For a reduced frame the map
  // is completed by reciprocity first and read back from its upper triangle (d < m).
  // Precomputed as index tables from paper_algorithm (below), which they equal exactly.
  Eigen::VectorXd apply_paper(const GroupElement& g, const Eigen::VectorXd& frame,
                              FrameLayout layout) const;
  const std::vector<int>& paper_permutation(const GroupElement& g, FrameLayout layout) const;
  Eigen::VectorXd apply(AugmentGroup group, const GroupElement& g, const Eigen::VectorXd& frame,
                        FrameLayout layout) const;
  // The index table that apply(group, g, ., layout) gathers through.
  const std::vector<int>& table(AugmentGroup group, const GroupElement& g,
                                FrameLayout layout) const;

 private:
  Protocol protocol_;
  std::vector<std::vector<int>> permutations_[3];        // [layout][element index 2L]
  std::vector<std::vector<int>> paper_permutations_[3];  // the same for apply_paper
};

// The paper's Algorithms 1 and 2 as written, on the impedance map (slow; FrameSymmetry's tables are
// made from it and tested against it).
Eigen::VectorXd paper_algorithm(const GroupElement& g, const Eigen::VectorXd& frame,
                                const Protocol& protocol, FrameLayout layout);

}  // namespace eitbench
