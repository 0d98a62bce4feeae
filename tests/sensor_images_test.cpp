// Images and data on a sensor of any shape: the grid covering its mesh, label images moved by the
// sensor's own group (exact where the group permutes the grid's pixels), the simulation's touches
// inside the shape, its refined mesh, and the data set that records the sensor.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "eitbench/augment.h"
#include "eitbench/bench/data/dataset_file.h"
#include "eitbench/bench/data/sensor.h"
#include "eitbench/bench/data/simulate.h"
#include "eitbench/jacobian.h"
#include "eitbench/jacobian/shape_mesh.h"
#include "eitbench/solvers.h"

namespace eitbench {
namespace {

Mesh shape_mesh(SensorShape shape, double width, double height) {
  ShapeMeshOptions o;
  o.shape = shape;
  o.width = width;
  o.height = height;
  o.density = MeshDensity::coarse;
  return generate_shape_mesh(o);
}

const Mesh& square_mesh() {
  static const Mesh mesh = shape_mesh(SensorShape::rectangle, 2, 2);
  return mesh;
}

const Mesh& ellipse() {  // 2:1
  static const Mesh mesh = shape_mesh(SensorShape::ellipse, 2, 1);
  return mesh;
}

TEST(SensorGrid, CoversTheMeshsBoundingBoxAndMasksWhatLiesOutside) {
  const PixelGrid sq = PixelGrid::covering(square_mesh(), 32);
  EXPECT_FALSE(sq.is_disk());
  EXPECT_NEAR(sq.radius(), 1.0, 1e-12);
  EXPECT_NEAR(sq.box_centre().norm(), 0.0, 1e-12);
  EXPECT_EQ(sq.num_inside(), 32 * 32);  // every pixel centre of the square lies in it

  // The ellipse covers pi a b of its box's 4: its unmasked pixels' area within a pixel row of it.
  const PixelGrid el = PixelGrid::covering(ellipse(), 64);
  const double w = el.pixel_width();
  EXPECT_NEAR(el.num_inside() * w * w, M_PI * 1.0 * 0.5, 2 * 2 * M_PI * w);
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const Eigen::Vector2d c = el.center(i, j);
      const double r = std::hypot(c.x() / 1.0, c.y() / 0.5);
      if (std::abs(r - 1) > 0.05) {
        EXPECT_EQ(el.mask()[i * 64 + j], r < 1) << i << "," << j;
      }
    }

  // A sensor away from the origin: the box follows it, the mask is the same.
  Mesh moved = ellipse();
  moved.nodes.col(0).array() += 3.0, moved.nodes.col(1).array() -= 2.0;
  const PixelGrid far = PixelGrid::covering(moved, 64);
  EXPECT_NEAR((far.box_centre() - Eigen::Vector2d(3, -2)).norm(), 0, 1e-12);
  EXPECT_TRUE((far.mask() == el.mask()).all());
  EXPECT_NEAR((far.center(17, 40) - el.center(17, 40) - Eigen::Vector2d(3, -2)).norm(), 0, 1e-12);
}

TEST(SensorGrid, TheDisksGridIsUnchanged) {
  const PixelGrid disk(64, 1.0);
  EXPECT_TRUE(disk.is_disk());
  EXPECT_EQ(disk.left(), -1.0);
  EXPECT_EQ(disk.top(), 1.0);
  int inside = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const double x = -1 + (j + 0.5) / 32, y = 1 - (i + 0.5) / 32;
      inside += std::hypot(x, y) < 1;
      EXPECT_EQ(disk.center(i, j), Eigen::Vector2d(x, y));
    }
  EXPECT_EQ(disk.num_inside(), inside);
}

TEST(SensorGrid, TheLinearProblemAcceptsTheGridOfItsOwnMeshOnly) {
  const auto model = std::make_shared<const ForwardModel>(square_mesh(), ForwardOptions{});
  const LinearProblem p = make_linear_problem(model, 1.0, PixelGrid::covering(square_mesh(), 32));
  EXPECT_EQ(p.unknowns(), 32 * 32);
  // Element conductivities from pixels: every row of P sums to one.
  const Eigen::VectorXd ones = p.element_from_pixels * Eigen::VectorXd::Ones(p.unknowns());
  EXPECT_NEAR((ones.array() - 1).abs().maxCoeff(), 0, 1e-12);
  // The ellipse's grid on the square's mesh: not this sensor's.
  EXPECT_THROW(make_linear_problem(model, 1.0, PixelGrid::covering(ellipse(), 32)), InputError);
}

// Each element of the sensor's group moves a label image as it moves the touches: on the square
// (D4) and the ellipse (D2) centred in their boxes, every element permutes the pixels, so the
// bilinear stencil equals re-rasterising the moved circles up to rounding.
TEST(SensorImages, LabelsMoveAsTheirTouchesUnderEveryElement) {
  Mesh away = ellipse();  // the same ellipse off the origin: its box and isometries move with it
  away.nodes.col(0).array() += 3.0, away.nodes.col(1).array() -= 2.0;
  for (const Mesh* mesh : {&square_mesh(), &ellipse(), static_cast<const Mesh*>(&away)}) {
    const auto sensor = std::make_shared<const ShapedSensor>(shaped_sensor(*mesh, 48));
    const ImageSymmetry images(sensor);
    const Eigen::Vector2d o = sensor->grid.box_centre();
    const std::vector<Circle> touches{{o.x() + 0.31, o.y() + 0.07, 0.12, 0.01},
                                      {o.x() - 0.4, o.y() - 0.1, 0.08, 0.03}};
    const Eigen::VectorXd label = circles_image(sensor->grid, touches, 0.05);
    ASSERT_GT(label.sum(), 1);
    for (const SensorSymmetry& s : sensor->group.elements) {
      const Eigen::VectorXd exact =
          circles_image(sensor->grid, images.move(touches, s.element), 0.05);
      // The isometry is found from the mesh's nodes (its centroid to about 1e-9), so the stencil
      // is a permutation up to that; interpolation would miss by percents (augment_test).
      EXPECT_LT((images.apply(s.element, label) - exact).lpNorm<Eigen::Infinity>(), 1e-6)
          << sensor->group.name() << " " << s.element.to_string();
    }
    // An element the sensor lacks is refused, naming it.
    EXPECT_THROW(images.apply({1, false}, label), InputError);
  }
}

TEST(SensorImages, AugmentationTakesTheSensorsElements) {
  AugmentSetup setup;
  setup.image_size = 16;
  setup.sensor = std::make_shared<const ShapedSensor>(shaped_sensor(square_mesh(), 16));
  const std::pair<AugmentGroup, std::size_t> expected[] = {{AugmentGroup::dihedral, 8},
                                                           {AugmentGroup::rotations, 4},
                                                           {AugmentGroup::mirror, 2},
                                                           {AugmentGroup::none, 1}};
  for (const auto& [group, count] : expected) {
    setup.group = group;
    EXPECT_EQ(augment_elements(setup).size(), count) << to_string(group);
  }
  setup.group = AugmentGroup::paper;
  EXPECT_THROW(augment_elements(setup), InputError);

  // Expanded: each frame times 8, each copy's label the re-rasterised moved circles.
  setup.group = AugmentGroup::dihedral;
  LabelledFrames set;
  set.background = 0.05;
  set.frames = SampleMatrix::Random(2, 104);
  set.circles = {{{0.3, 0.2, 0.1, 0.01}}, {{-0.5, 0.4, 0.2, 0.02}}};
  const LabelledFrames out = expand_by_group(set, setup);
  ASSERT_EQ(out.frames.rows(), 16);
  const ImageSymmetry images(setup.sensor);
  const auto elements = augment_elements(setup);
  for (int k = 0; k < 8; ++k) {
    const auto moved = images.move(set.circles[1], elements[k]);
    EXPECT_NEAR(out.circles[8 + k][0].x, moved[0].x, 1e-12);
    EXPECT_LT((out.labels.row(8 + k).transpose() - circles_image(setup.sensor->grid, moved, 0.05))
                  .lpNorm<Eigen::Infinity>(),
              1e-12);
  }
}

TEST(SensorData, RefinedMeshIsTheSameSensorFourTimesFiner) {
  const Mesh fine = refine_mesh(square_mesh());
  EXPECT_NO_THROW(validate_mesh(fine, "refined"));
  EXPECT_EQ(fine.num_triangles(), 4 * square_mesh().num_triangles());
  EXPECT_NEAR(triangle_areas(fine).sum(), triangle_areas(square_mesh()).sum(), 1e-12);
  ASSERT_EQ(fine.num_electrodes(), 16);
  for (int e = 0; e < 16; ++e)
    EXPECT_NEAR(fine.electrodes[e].length(fine.nodes),
                square_mesh().electrodes[e].length(square_mesh().nodes), 1e-12);
  // The same physics: the empty sensor's frames converge as the mesh is refined again (each
  // refinement changes them less), and so do not drift to another sensor's.
  const Mesh finer = refine_mesh(fine);
  auto frame = [](const Mesh& mesh) {
    return ForwardModel(mesh, ForwardOptions{}).frame(Eigen::VectorXd::Ones(mesh.num_triangles()));
  };
  const Eigen::VectorXd a = frame(square_mesh()), b = frame(fine), c = frame(finer);
  const double first = (a - b).norm() / b.norm(), second = (b - c).norm() / c.norm();
  EXPECT_LT(first, 0.1);
  EXPECT_LT(second, 0.6 * first) << first << " then " << second;
}

TEST(SensorData, SimulatedSetKeepsTouchesInsideAndRecordsItsSensor) {
  SimulationOptions o;
  o.preset = "tiny";
  o.image_size = 32;
  o.sensor_mesh = std::make_shared<const Mesh>(ellipse());
  o.sensor_source = "ellipse.msh";
  const Dataset d = simulate_dataset(o);
  EXPECT_EQ(d.sensor_group, "D2");
  EXPECT_EQ(d.simulation_mesh, "ellipse.msh, refined once");
  for (const auto& circles : d.circles)
    for (const Circle& c : circles)  // every rim point inside the 2 x 1 ellipse
      for (int k = 0; k < 64; ++k) {
        const double x = c.x + c.r * std::cos(k * M_PI / 32),
                     y = c.y + c.r * std::sin(k * M_PI / 32);
        EXPECT_LE(x * x + 4 * y * y, 1.0 + 1e-9);
      }
  const PixelGrid grid = image_grid(d);
  for (int i = 0; i < d.size(); ++i)
    for (int p = 0; p < grid.num_pixels(); ++p)
      if (!grid.mask()[p]) {
        ASSERT_EQ(d.labels(i, p), 0.0);
      }

  // Through the file and back: the same sensor, its mesh and group.
  const std::string path =
      (std::filesystem::temp_directory_path() / "eitbench_sensor_set.h5").string();
  write_dataset(path, d);
  const Dataset back = read_dataset(path);
  std::filesystem::remove(path);
  EXPECT_EQ(back.sensor_mesh, d.sensor_mesh);
  EXPECT_EQ(back.sensor_group, "D2");
  const Mesh mesh = stored_sensor_mesh(back);
  EXPECT_EQ(mesh.num_triangles(), ellipse().num_triangles());
  EXPECT_LT((mesh.nodes - ellipse().nodes).lpNorm<Eigen::Infinity>(), 1e-15);
  EXPECT_EQ(shaped_sensor_of(back)->group.order(), 4);
  SimulationOptions disk;
  disk.preset = "tiny", disk.density = MeshDensity::coarse;
  EXPECT_EQ(shaped_sensor_of(simulate_dataset(disk)), nullptr);  // the disk stores no mesh
}

// GREIT's targets and the shape fit follow the sensor: on the square, one touch's frame (made on
// the refined mesh) puts GREIT's peak and the fitted circle where the touch is, near a side too.
TEST(SensorMethods, GreitAndTheShapeFitFindATouchOnTheSquare) {
  const auto model = std::make_shared<const ForwardModel>(square_mesh(), ForwardOptions{});
  const double background = 0.05;
  const auto problem = std::make_shared<const LinearProblem>(
      make_linear_problem(model, background, PixelGrid::covering(square_mesh(), 32)));
  const Mesh fine = refine_mesh(square_mesh());
  const ForwardModel truth_model(fine, ForwardOptions{});
  const Eigen::VectorXd empty =
      truth_model.frame(Eigen::VectorXd::Constant(fine.num_triangles(), background));
  GreitOptions go;
  go.targets = 300;
  const Greit greit(problem, go);
  ShapeOptions so;
  so.forward = ShapeForward::linear;
  const ShapeReconstructor shape(problem, so);
  for (const Circle& touch : {Circle{0.35, -0.2, 0.15, 0.005}, Circle{-0.62, 0.55, 0.15, 0.005}}) {
    const Eigen::VectorXd frame =
        truth_model.frame(conductivity_from_circles(fine, {touch}, background)) - empty;
    const Eigen::VectorXd dv = model->protocol().reduce(frame, MeasurementOrder::rotating);
    Eigen::Index peak;
    greit.reconstruct(dv).maxCoeff(&peak);
    const Eigen::Vector2d at =
        problem->grid.center(static_cast<int>(peak / 32), static_cast<int>(peak % 32));
    EXPECT_LT((at - Eigen::Vector2d(touch.x, touch.y)).norm(), 0.2) << touch.x;
    Eigen::VectorXd image;
    const std::vector<Circle> found = shape.touches(dv, image);
    ASSERT_GE(found.size(), 1u);
    EXPECT_LT(std::hypot(found[0].x - touch.x, found[0].y - touch.y), 0.05) << touch.x;
    for (const Circle& c : found)  // inside the square
      EXPECT_LE(std::max(std::abs(c.x), std::abs(c.y)) + c.r, 1.0 + 1e-6);
  }
}

TEST(SensorData, ASensorTooThinForItsTouchesIsRefused) {
  ShapeMeshOptions thin;
  thin.width = 2, thin.height = 0.1, thin.density = MeshDensity::coarse;
  SimulationOptions o;
  o.preset = "tiny";
  o.sensor_mesh = std::make_shared<const Mesh>(generate_shape_mesh(thin));
  try {
    simulate_dataset(o);
    ADD_FAILURE() << "simulated touches that cannot fit";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no room for"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace eitbench
