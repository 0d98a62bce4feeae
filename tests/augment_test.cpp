// The symmetry group against the forward model: for every g in D_L, the frame of the moved touch
// equals the transformed frame. Plus the group laws, the impedance map, the paper's variants,
// label transforms and data-set augmentation.
#include <gtest/gtest.h>

#include <tbb/global_control.h>
#include <opencv2/imgproc.hpp>

#include <random>
#include <set>

#include "eitbench/augment.h"
#include "eitbench/jacobian.h"
#include "group_support.h"
#include "test_support.h"

namespace eitbench {
namespace {

TEST(Group, TransformPointIsRotationByMinusSStepsAfterTheMirror) {
  const Eigen::Vector2d p(0.3, 0.4);
  const Eigen::Vector2d r = transform_point(p, {3, false}, 16);
  const double a = -2 * M_PI * 3 / 16;
  EXPECT_NEAR(r.x(), std::cos(a) * 0.3 - std::sin(a) * 0.4, 1e-15);
  EXPECT_NEAR(r.y(), std::sin(a) * 0.3 + std::cos(a) * 0.4, 1e-15);
  const Eigen::Vector2d m = transform_point(p, {0, true}, 16);
  EXPECT_NEAR(m.x(), 0.3, 1e-15);
  EXPECT_NEAR(m.y(), -0.4, 1e-15);
}

TEST(Group, Laws) {
  for (int L : {8, 16, 32}) {
    const GroupElement id{0, false}, rot{1, false}, mirror{0, true};
    GroupElement power = id;
    for (int k = 0; k < L; ++k) power = compose(rot, power, L);
    EXPECT_EQ(power, id) << "rot^L = id";
    EXPECT_EQ(compose(mirror, mirror, L), id) << "mirror^2 = id";
    for (int s = 0; s < L; ++s) {
      EXPECT_EQ(compose(mirror, GroupElement{s, false}, L),
                compose(GroupElement{(L - s) % L, false}, mirror, L));
      for (bool m : {false, true}) {
        const GroupElement g{s, m};
        EXPECT_EQ(compose(g, inverse(g, L), L), id);
        EXPECT_EQ(compose(inverse(g, L), g, L), id);
      }
    }
    // Composition agrees with the action on points and on frames.
    const FrameSymmetry sym(L);
    std::mt19937 rng(L);
    std::normal_distribution<double> n;
    Eigen::VectorXd v(sym.protocol().reduced_size());
    for (auto& x : v) x = n(rng);
    const Eigen::Vector2d p(0.31, -0.12);
    for (const GroupElement& g : group_elements(AugmentGroup::dihedral, L))
      for (const GroupElement& h : {GroupElement{3 % L, false}, GroupElement{5 % L, true}}) {
        const GroupElement gh = compose(g, h, L);
        EXPECT_LT(
            (transform_point(transform_point(p, h, L), g, L) - transform_point(p, gh, L)).norm(),
            1e-14);
        EXPECT_EQ(sym.apply(g, sym.apply(h, v, FrameLayout::reduced), FrameLayout::reduced),
                  sym.apply(gh, v, FrameLayout::reduced));
      }
  }
}

TEST(Group, ParseAndPrintElements) {
  EXPECT_EQ(parse_element("rot:3", 16), (GroupElement{3, false}));
  EXPECT_EQ(parse_element("mirror:0", 16), (GroupElement{0, true}));
  EXPECT_EQ(parse_element("rot:-1", 16), (GroupElement{15, false}));
  EXPECT_EQ(parse_element("rot:17", 16), (GroupElement{1, false}));
  EXPECT_EQ(GroupElement({5, true}).to_string(), "mirror:5");
  for (const char* bad : {"rot", "rot:", "rot:x", "spin:1", "mirror:1.5", ""})
    EXPECT_THROW(parse_element(bad, 16), InputError) << bad;
  EXPECT_EQ(parse_group("d16"), AugmentGroup::dihedral);
  EXPECT_THROW(parse_group("d8x"), InputError);
  // Unless the caller names where the name came from (the command line passes its flag), the
  // error names what was being parsed.
  EXPECT_EQ(testing::input_error_at([] { parse_group("d8x"); }), "AugmentGroup.");
  EXPECT_EQ(testing::input_error_at([] { parse_group("d8x", "--group"); }), "--group.");
  EXPECT_EQ(testing::input_error_at([] { parse_element("spin:1", 16); }), "GroupElement.");
  EXPECT_EQ(group_elements(AugmentGroup::dihedral, 16).size(), 32u);
  EXPECT_EQ(group_elements(AugmentGroup::rotations, 16).size(), 16u);
  EXPECT_EQ(group_elements(AugmentGroup::mirror, 16).size(), 2u);
  EXPECT_EQ(group_elements(AugmentGroup::none, 16).size(), 1u);
}

class ForwardCommutes : public ::testing::TestWithParam<int> {};

TEST_P(ForwardCommutes, WithEveryGroupElementOnASymmetricMesh) {
  const int L = GetParam();
  const Mesh& mesh = testing::disk(L, MeshDensity::coarse);
  const ForwardModel model(mesh);
  const FrameSymmetry sym(L);
  const Eigen::VectorXd sigma = testing::random_conductivity(mesh.num_triangles(), 21);
  const Eigen::VectorXd v = model.frame(sigma);
  double worst = 0;
  for (const GroupElement& g : group_elements(AugmentGroup::dihedral, L)) {
    const Eigen::VectorXd simulated = model.frame(testing::move_conductivity(mesh, sigma, g));
    for (auto layout : {FrameLayout::rotating, FrameLayout::ascending}) {
      const MeasurementOrder order = layout == FrameLayout::rotating ? MeasurementOrder::rotating
                                                                     : MeasurementOrder::ascending;
      const Eigen::VectorXd transformed =
          sym.apply(g, model.protocol().reorder(v, MeasurementOrder::rotating, order), layout);
      const double error =
          (transformed - model.protocol().reorder(simulated, MeasurementOrder::rotating, order))
              .norm() /
          v.norm();
      worst = std::max(worst, error);
      EXPECT_LT(error, 1e-10) << g.to_string() << " " << to_string(layout);
    }
    const Eigen::VectorXd reduced =
        sym.apply(g, model.protocol().reduce(v, MeasurementOrder::rotating), FrameLayout::reduced);
    EXPECT_LT((reduced - model.protocol().reduce(simulated, MeasurementOrder::rotating)).norm() /
                  v.norm(),
              1e-10);
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
}

INSTANTIATE_TEST_SUITE_P(L, ForwardCommutes, ::testing::Values(8, 16));

TEST(Circles, SimulatingMovedCirclesEqualsMovingTheFrame) {
  const std::vector<Circle> touch{
      {0.42, 0.13, 0.21, 0.01}, {-0.25, -0.4, 0.12, 0.03}, {0.05, 0.55, 0.09, 0.005}};
  const double background = 0.05;
  const int L = 16;
  const FrameSymmetry sym(L);
  // On the symmetric mesh the circle overlaps move with the triangles: agreement to round-off.
  // On a mesh without the symmetry (the same mesh with its interior nodes jittered) the
  // discretisation differs between a touch and its image: that error is measured and bounded.
  Mesh jittered = testing::disk(L, MeshDensity::medium);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.004, 0.004);
  for (int i = 0; i < jittered.num_nodes(); ++i)
    if (jittered.nodes.row(i).norm() < 0.98)
      jittered.nodes.row(i) += Eigen::RowVector2d(u(rng), u(rng));
  struct Case {
    const Mesh* mesh;
    double tolerance;
  };
  for (const auto& [mesh, tolerance] :
       {Case{&testing::disk(L, MeshDensity::medium), 1e-9}, Case{&jittered, 2e-2}}) {
    const ForwardModel model(*mesh);
    const Eigen::VectorXd ref =
        model.frame(Eigen::VectorXd::Constant(mesh->num_triangles(), background));
    const Eigen::VectorXd dv =
        model.frame(conductivity_from_circles(*mesh, touch, background)) - ref;
    double worst = 0;
    for (const GroupElement& g : group_elements(AugmentGroup::dihedral, L)) {
      const Eigen::VectorXd moved = model.frame(conductivity_from_circles(
                                        *mesh, transform_circles(touch, g, L), background)) -
                                    ref;
      // The reference frame is invariant on the symmetric mesh, so the difference frames transform
      // too.
      worst =
          std::max(worst, (sym.apply(g, dv, FrameLayout::rotating) - moved).cwiseAbs().maxCoeff() /
                              dv.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, tolerance);
    RecordProperty(tolerance < 1e-6 ? "symmetric_mesh_error" : "jittered_mesh_error",
                   std::to_string(worst));
    std::printf("circles: worst error relative to max |dv|: %.3g (%s mesh)\n", worst,
                tolerance < 1e-6 ? "symmetric" : "jittered");
  }
}

TEST(ImpedanceMap, RoundTripsAndLayout) {
  const Protocol p(16);
  std::mt19937 rng(1);
  std::normal_distribution<double> n;
  Eigen::VectorXd reduced(104);
  for (auto& x : reduced) x = n(rng);
  const Eigen::MatrixXd map = impedance_map(reduced, p, FrameLayout::reduced);
  ASSERT_EQ(map.rows(), 16);
  ASSERT_EQ(map.cols(), 13);
  EXPECT_EQ(frame_from_map(map, p, FrameLayout::reduced), reduced);
  const Eigen::VectorXd full = p.expand(reduced, MeasurementOrder::rotating);
  EXPECT_EQ(frame_from_map(map, p, FrameLayout::rotating), full);
  EXPECT_EQ(map(3, 4), full[p.index(3, 3 + 2 + 4, MeasurementOrder::rotating)]);
  const Eigen::MatrixXd square = full_impedance_map(reduced, p, FrameLayout::reduced);
  for (int d = 0; d < 16; ++d)
    for (int m = 0; m < 16; ++m) {
      if (p.index(d, m, MeasurementOrder::rotating) < 0) {
        EXPECT_TRUE(std::isnan(square(d, m)));
      } else {
        EXPECT_EQ(square(d, m), square(m, d));
      }
    }
  EXPECT_EQ(frame_layout(104, 16, MeasurementOrder::rotating, "x"), FrameLayout::reduced);
  EXPECT_EQ(frame_layout(208, 16, MeasurementOrder::ascending, "x"), FrameLayout::ascending);
  EXPECT_THROW(frame_layout(103, 16, MeasurementOrder::rotating, "x"), InputError);
  EXPECT_THROW(frame_layout(208, 8, MeasurementOrder::rotating, "x"), InputError);
}

// Frames, maps and images are data: one of the wrong size is bad input, not a programming error.
TEST(ImpedanceMap, DataOfTheWrongSizeIsBadInput) {
  using testing::input_error_at;
  const Protocol p(16);
  const Eigen::VectorXd short_frame = Eigen::VectorXd::Ones(103);
  EXPECT_EQ(input_error_at([&] { impedance_map(short_frame, p, FrameLayout::reduced); }),
            "frame.values");
  EXPECT_EQ(input_error_at(
                [&] { frame_from_map(Eigen::MatrixXd::Ones(16, 16), p, FrameLayout::reduced); }),
            "map.shape");
  const FrameSymmetry symmetry(16);
  EXPECT_EQ(input_error_at([&] {
              symmetry.apply({1, false}, short_frame, FrameLayout::reduced);
            }),
            "frame.values");
  const ImageSymmetry images(16, PixelGrid(16, 1.0));
  EXPECT_EQ(input_error_at([&] {
              images.apply({1, false}, Eigen::VectorXd::Ones(255));
            }),
            "image.pixels");
}

TEST(Paper, AlgorithmOneEqualsTheRotations) {
  const FrameSymmetry sym(16);
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd v =
      ForwardModel(mesh).frame(testing::random_conductivity(mesh.num_triangles(), 4));
  for (auto layout : {FrameLayout::rotating, FrameLayout::reduced}) {
    const Eigen::VectorXd frame =
        layout == FrameLayout::reduced ? sym.protocol().reduce(v, MeasurementOrder::rotating) : v;
    for (int s = 0; s < 16; ++s)
      EXPECT_LT((sym.apply_paper({s, false}, frame, layout) - sym.apply({s, false}, frame, layout))
                    .norm(),
                1e-15 * v.norm());
  }
}

TEST(Paper, AlgorithmTwoIsNoPhysicalMirror) {
  // The conventions' finding (docs/augmentation.md): on a D16-symmetric network the paper's column
  // reversal differs from every physically mirrored frame by 8-14 % of the signal's maximum, and
  // breaks reciprocity.
  const int L = 16;
  const Mesh& mesh = testing::disk(L, MeshDensity::medium);
  const ForwardModel model(mesh);
  const FrameSymmetry sym(L);
  const std::vector<Circle> touch{{0.42, 0.13, 0.21, 0.01}, {-0.25, -0.4, 0.12, 0.03}};
  const Eigen::VectorXd ref = model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), 0.05));
  for (const Eigen::VectorXd& v :
       {Eigen::VectorXd(model.frame(testing::random_conductivity(mesh.num_triangles(), 8))),
        Eigen::VectorXd(model.frame(conductivity_from_circles(mesh, touch, 0.05)) - ref)}) {
    const Eigen::VectorXd paper = sym.apply_paper({0, true}, v, FrameLayout::rotating);
    double closest = INFINITY;
    for (int s = 0; s < L; ++s)
      closest = std::min(
          closest, (paper - sym.apply({s, true}, v, FrameLayout::rotating)).cwiseAbs().maxCoeff() /
                       v.cwiseAbs().maxCoeff());
    std::printf(
        "paper mirror: closest physical mirror differs by %.1f %% of max |v|; reciprocity error "
        "%.3f\n",
        100 * closest, sym.protocol().reciprocity_error(paper, MeasurementOrder::rotating));
    EXPECT_GT(closest, 0.05);
    EXPECT_GT(sym.protocol().reciprocity_error(paper, MeasurementOrder::rotating), 1e-3);
    EXPECT_LT(sym.protocol().reciprocity_error(sym.apply({0, true}, v, FrameLayout::rotating),
                                               MeasurementOrder::rotating),
              1e-12);
    // What Algorithm 2 does: row d is the mirror about the gap between electrodes d and d+1.
    const Eigen::MatrixXd map = impedance_map(paper, sym.protocol(), FrameLayout::rotating);
    const Eigen::MatrixXd full = full_impedance_map(v, sym.protocol(), FrameLayout::rotating);
    for (int d = 0; d < L; ++d)
      for (int k = 0; k < L - 3; ++k)
        EXPECT_EQ(map(d, k), full(d, ((2 * d - (d + 2 + k)) % L + L) % L));
  }
}

// The augmentation as tables: every element's action on frames is an index gather, made once by
// running the paper's Algorithms on a frame of indices; it must equal the Algorithms run on real
// frames, exactly, for every element and layout.
TEST(Tables, PaperGathersEqualTheAlgorithmsForEveryElement) {
  const FrameSymmetry sym(16);
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd v =
      ForwardModel(mesh).frame(testing::random_conductivity(mesh.num_triangles(), 6));
  for (auto layout : {FrameLayout::rotating, FrameLayout::ascending, FrameLayout::reduced}) {
    const Eigen::VectorXd frame =
        layout == FrameLayout::reduced ? sym.protocol().reduce(v, MeasurementOrder::rotating)
        : layout == FrameLayout::ascending
            ? sym.protocol().reorder(v, MeasurementOrder::rotating, MeasurementOrder::ascending)
            : v;
    for (const GroupElement& g : group_elements(AugmentGroup::paper, 16))
      EXPECT_EQ(sym.apply_paper(g, frame, layout),
                paper_algorithm(g, frame, sym.protocol(), layout))
          << g.to_string() << " layout " << static_cast<int>(layout);
  }
}

// Labels as tables: each element's bilinear stencil against OpenCV's remap through the same
// sampling points, an implementation that shares nothing with it. OpenCV quantises bilinear
// weights to 1/32 of a pixel in each direction, so the two agree to 1/32 of the image's range.
TEST(Tables, LabelStencilsEqualBilinearRemapForEveryElement) {
  const PixelGrid grid(64, 1.0);
  const int n = grid.size();
  const std::vector<Circle> touch{{0.42, 0.13, 0.21, 0.01}, {-0.25, -0.4, 0.12, 0.03}};
  const Eigen::VectorXd image = circles_image(grid, touch, 0.05);
  const ImageSymmetry images(16, grid);
  double worst = 0;
  for (const GroupElement& g : group_elements(AugmentGroup::dihedral, 16)) {
    cv::Mat mx(n, n, CV_32F), my(n, n, CV_32F);
    const GroupElement inv = inverse(g, 16);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Eigen::Vector2d source = transform_point(grid.center(i, j), inv, 16);
        mx.at<float>(i, j) = static_cast<float>((source.x() + 1) / grid.pixel_width() - 0.5);
        my.at<float>(i, j) = static_cast<float>((1 - source.y()) / grid.pixel_width() - 0.5);
      }
    const cv::Mat in(n, n, CV_64F, const_cast<double*>(image.data()));
    Eigen::VectorXd reference(image.size());
    cv::Mat out(n, n, CV_64F, reference.data());
    cv::remap(in, out, mx, my, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0.0);
    for (int p = 0; p < grid.num_pixels(); ++p)
      if (!grid.mask()[p]) reference[p] = 0;
    const double gap = (images.apply(g, image) - reference).cwiseAbs().maxCoeff();
    worst = std::max(worst, gap);
    EXPECT_LE(gap, image.maxCoeff() / 32) << g.to_string();
  }
  std::printf("label stencil against OpenCV remap: largest difference %.4f of %.4f\n", worst,
              image.maxCoeff());
}

TEST(Augment, AGenericTouchHas32DistinctFrames) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const Eigen::VectorXd v =
      ForwardModel(mesh).frame(testing::random_conductivity(mesh.num_triangles(), 9));
  const FrameSymmetry sym(16);
  std::vector<Eigen::VectorXd> frames;
  for (const GroupElement& g : group_elements(AugmentGroup::dihedral, 16))
    frames.push_back(sym.apply(g, v, FrameLayout::rotating));
  for (std::size_t a = 0; a < frames.size(); ++a)
    for (std::size_t b = a + 1; b < frames.size(); ++b)
      EXPECT_GT((frames[a] - frames[b]).cwiseAbs().maxCoeff(), 1e-6 * v.cwiseAbs().maxCoeff())
          << a << " vs " << b;
}

TEST(Labels, MirrorAndQuarterTurnsAreExactPixelPermutations) {
  const PixelGrid grid(64, 1.0);
  const std::vector<Circle> touch{{0.42, 0.13, 0.21, 0.01}, {-0.25, -0.4, 0.12, 0.03}};
  const Eigen::VectorXd image = circles_image(grid, touch, 0.05);
  for (const GroupElement& g : {GroupElement{0, true}, GroupElement{4, false},
                                GroupElement{8, true}, GroupElement{12, false}}) {
    const Eigen::VectorXd exact = circles_image(grid, transform_circles(touch, g, 16), 0.05);
    EXPECT_LT((transform_image(image, g, 16, grid) - exact).cwiseAbs().maxCoeff(), 1e-12)
        << g.to_string();
  }
}

TEST(Labels, BilinearRotationErrorIsBounded) {
  // Against exact re-rasterisation of the moved circles; the figure goes into the README.
  const PixelGrid grid(64, 1.0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> pos(-0.5, 0.5), radius(0.05, 0.25);
  double worst = 0, sum = 0;
  int count = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Circle> touch{{pos(rng), pos(rng), radius(rng), 0.001}};
    const Eigen::VectorXd image = circles_image(grid, touch, 0.05);
    for (const GroupElement& g : group_elements(AugmentGroup::dihedral, 16)) {
      const Eigen::VectorXd exact = circles_image(grid, transform_circles(touch, g, 16), 0.05);
      const double error = (transform_image(image, g, 16, grid) - exact).norm() / exact.norm();
      worst = std::max(worst, error);
      sum += error;
      ++count;
    }
  }
  std::printf("bilinear label transform: relative L2 error mean %.3f, worst %.3f\n", sum / count,
              worst);
  EXPECT_LT(sum / count, 0.10);
  EXPECT_LT(worst, 0.25);
}

LabelledFrames circle_set(const Mesh& mesh, int n, unsigned seed) {
  const ForwardModel model(mesh);
  const PixelGrid grid(64, 1.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-0.45, 0.45), radius(0.08, 0.2), cond(0.001, 0.04);
  LabelledFrames set;
  set.background = 0.05;  // the labels below are relative to 0.05
  set.frames.resize(n, 104);
  set.labels.resize(n, 4096);
  const Eigen::VectorXd ref = model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), 0.05));
  for (int i = 0; i < n; ++i) {
    set.circles.push_back({{pos(rng), pos(rng), radius(rng), cond(rng)}});
    const Eigen::VectorXd dv =
        model.frame(conductivity_from_circles(mesh, set.circles.back(), 0.05)) - ref;
    set.frames.row(i) = model.protocol().reduce(dv, MeasurementOrder::rotating).transpose();
    set.labels.row(i) = circles_image(grid, set.circles.back(), 0.05).transpose();
  }
  return set;
}

TEST(Augment, ExpandedPairsAgreeWithTheForwardModel) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const LabelledFrames set = circle_set(mesh, 3, 1);
  AugmentSetup setup;
  const LabelledFrames big = expand_by_group(set, setup);
  ASSERT_EQ(big.frames.rows(), 3 * 32);
  const ForwardModel model(mesh);
  const Eigen::VectorXd ref = model.frame(Eigen::VectorXd::Constant(mesh.num_triangles(), 0.05));
  const PixelGrid grid(64, 1.0);
  for (int row = 0; row < big.frames.rows(); row += 7) {
    // The pair (frame, label) of every row is what the forward model gives for its circles.
    const Eigen::VectorXd dv =
        model.frame(conductivity_from_circles(mesh, big.circles[row], 0.05)) - ref;
    EXPECT_LT(
        (model.protocol().reduce(dv, MeasurementOrder::rotating) - big.frames.row(row).transpose())
            .norm(),
        1e-9 * dv.norm());
    EXPECT_LT(
        (circles_image(grid, big.circles[row], 0.05) - big.labels.row(row).transpose()).norm(),
        1e-12);
  }
  setup.group = AugmentGroup::rotations;
  EXPECT_EQ(expand_by_group(set, setup).frames.rows(), 3 * 16);
}

TEST(Augment, ExpansionIsIdenticalForAnyThreadCount) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  LabelledFrames set = circle_set(mesh, 6, 3);
  AugmentSetup setup;
  const LabelledFrames many = expand_by_group(set, setup);
  LabelledFrames one;
  {
    const tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = expand_by_group(set, setup);
  }
  EXPECT_EQ(one.frames, many.frames);
  EXPECT_EQ(one.labels, many.labels);
  set.circles.clear();  // the bilinear path too
  EXPECT_EQ(expand_by_group(set, setup).labels.rows(), 6 * 32);
}

TEST(Augment, OnTheFlyIsDeterministicUniformAndConsistent) {
  const Mesh& mesh = testing::disk(16, MeshDensity::coarse);
  const auto shared = std::make_shared<const LabelledFrames>(circle_set(mesh, 4, 2));
  const LabelledFrames& set = *shared;
  AugmentSetup setup;
  const OnTheFlyAugmenter a(shared, setup, 42), b(shared, setup, 42), c(shared, setup, 43);
  std::map<std::string, int> counts;
  int differ = 0;
  for (int epoch = 0; epoch < 800; ++epoch)
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(a.element(i, epoch), b.element(i, epoch));
      differ += a.element(i, epoch) != c.element(i, epoch);
      ++counts[a.element(i, epoch).to_string()];
    }
  EXPECT_EQ(counts.size(), 32u);
  for (const auto& [name, n] : counts)
    EXPECT_NEAR(n, 100, 40) << name;  // 3200 draws over 32 elements
  EXPECT_GT(differ, 2800);            // another seed, other draws
  SampleMatrix frames, labels;
  a.batch({0, 1, 2, 3, 2}, 7, frames, labels);
  const FrameSymmetry sym(16);
  const PixelGrid grid(64, 1.0);
  for (int r = 0; r < 5; ++r) {
    const int i = r == 4 ? 2 : r;
    const GroupElement& g = a.element(i, 7);
    EXPECT_EQ(Eigen::VectorXd(frames.row(r).transpose()),
              sym.apply(g, set.frames.row(i).transpose(), FrameLayout::reduced));
    EXPECT_LT((labels.row(r).transpose() -
               circles_image(grid, transform_circles(set.circles[i], g, 16), 0.05))
                  .norm(),
              1e-12);
  }
  // Without circles, labels are moved bilinearly.
  // The augmenter shares its set: a temporary cannot dangle.
  LabelledFrames plain = set;
  plain.circles.clear();
  const OnTheFlyAugmenter d(std::make_shared<const LabelledFrames>(std::move(plain)), setup, 42);
  d.batch({1}, 3, frames, labels);
  EXPECT_LT((labels.row(0).transpose() -
             transform_image(set.labels.row(1).transpose(), d.element(1, 3), 16, grid))
                .norm(),
            1e-12);
}

TEST(Augment, RejectsBadSets) {
  LabelledFrames set;
  AugmentSetup setup;
  EXPECT_THROW(expand_by_group(set, setup), InputError);  // empty
  {  // circles without the background their labels are relative to
    LabelledFrames unset;
    unset.frames = SampleMatrix::Ones(1, 104);
    unset.labels = SampleMatrix::Zero(1, 4096);
    unset.circles = {{{0.1, 0.2, 0.2, 0.01}}};
    EXPECT_THROW(expand_by_group(unset, setup), InputError);
    unset.background = 0.05;
    EXPECT_NO_THROW(expand_by_group(unset, setup));
  }
  set.frames = SampleMatrix::Ones(2, 103);
  EXPECT_THROW(expand_by_group(set, setup), InputError);  // wrong length
  set.frames = SampleMatrix::Ones(2, 104);
  set.frames(1, 3) = NAN;
  EXPECT_THROW(expand_by_group(set, setup), InputError);
  set.frames(1, 3) = 1;
  set.labels = SampleMatrix::Ones(2, 100);
  EXPECT_THROW(expand_by_group(set, setup), InputError);
  setup.electrodes = 8;
  set.labels.resize(0, 0);
  EXPECT_THROW(expand_by_group(set, setup), InputError);  // 104 values do not fit L = 8
}

// The setup is validated before the augmenter builds its tables from it, naming the field.
TEST(Augment, SetupValidateNamesTheField) {
  using testing::input_error_at;
  EXPECT_EQ(input_error_at([] { AugmentSetup{}.validate(); }), "no InputError");
  LabelledFrames set;
  set.frames = SampleMatrix::Ones(2, 104);
  const auto shared = std::make_shared<const LabelledFrames>(set);
  const std::pair<void (*)(AugmentSetup&), std::string> cases[] = {
      {[](AugmentSetup& s) { s.electrodes = 3; }, "electrodes"},
      {[](AugmentSetup& s) { s.image_size = 0; }, "image_size"},
      {[](AugmentSetup& s) { s.radius = -1; }, "radius"},
  };
  for (const auto& [spoil, field] : cases) {
    AugmentSetup setup;
    spoil(setup);
    EXPECT_EQ(input_error_at([&] { setup.validate(); }), "AugmentSetup." + field);
    EXPECT_EQ(input_error_at([&] { expand_by_group(set, setup); }), "AugmentSetup." + field);
    EXPECT_EQ(input_error_at([&] { OnTheFlyAugmenter(shared, setup, 1); }),
              "AugmentSetup." + field);
  }
}

}  // namespace
}  // namespace eitbench
