// Touch metrics: blobs found in hand-drawn images where the circles were drawn, the exact matching
// against a case greedy matching gets wrong, the summary's percentiles on known numbers, the
// threshold chosen on validation, the stored form's round trip and the report's table.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "eitbench/bench/methods/press_scores.h"
#include "eitbench/bench/methods/touch_metrics.h"
#include "eitbench/bench/report/report.h"
#include "eitbench/bench/report/results.h"
#include "eitbench/bench/report/touch_report.h"
#include "eitbench/jacobian/pixel_grid.h"
#include "test_support.h"

namespace eitbench {
namespace {

namespace fs = std::filesystem;
using testing::kBackground;

// A circle of the given touch intensity (sigma_0 - sigma) / sigma_0.
Circle touch_circle(double x, double y, double r, double contrast) {
  return {x, y, r, kBackground * (1 - contrast)};
}

Eigen::VectorXd draw(const PixelGrid& grid, const std::vector<Circle>& circles) {
  return circles_image(grid, circles, kBackground);
}

// The found touch nearest (x, y).
const Touch& nearest(const std::vector<Touch>& found, double x, double y) {
  const Touch* best = &found.front();
  for (const Touch& t : found)
    if (std::hypot(t.x - x, t.y - y) < std::hypot(best->x - x, best->y - y)) best = &t;
  return *best;
}

TEST(TouchDetection, FindsDrawnCirclesAtTheirCentresAndSizes) {
  const PixelGrid grid(64, 2.0);  // R = 2: sensor units, not fractions of R
  const double w = grid.pixel_width();
  const std::vector<Circle> drawn = {touch_circle(-0.8, 0.4, 0.3, 0.8),
                                     touch_circle(0.7, -0.6, 0.4, 0.6)};
  const std::vector<Touch> found = find_touches(draw(grid, drawn), grid, 0.5);
  ASSERT_EQ(found.size(), 2u);
  for (const Circle& c : drawn) {
    const Touch& t = nearest(found, c.x, c.y);
    EXPECT_LT(std::hypot(t.x - c.x, t.y - c.y), 0.5 * w) << c.x;
    EXPECT_NEAR(t.r, c.r, w) << c.x;
    // Inside a drawn circle every pixel holds its full intensity: the peak is the contrast.
    EXPECT_NEAR(t.contrast, (kBackground - c.conductivity) / kBackground, 1e-9) << c.x;
  }
  // The truth's form of the same circles: the contrast back from the conductivity.
  const std::vector<Touch> truth = touches_of(drawn, kBackground);
  EXPECT_NEAR(truth[1].contrast, 0.6, 1e-12);
  EXPECT_EQ(truth[1].r, 0.4);
}

TEST(TouchDetection, TwoNearbyTouchesAreTwo) {
  const PixelGrid grid(64, 1.0);  // 0.03125 R a pixel; the circles are 0.1 R (3 pixels) apart
  const std::vector<Circle> drawn = {touch_circle(-0.2, 0.05, 0.15, 0.7),
                                     touch_circle(0.2, 0.05, 0.15, 0.7)};
  const std::vector<Touch> found = find_touches(draw(grid, drawn), grid, 0.3);
  ASSERT_EQ(found.size(), 2u);
  EXPECT_NEAR(nearest(found, -0.2, 0.05).x, -0.2, 0.5 * grid.pixel_width());
  EXPECT_NEAR(nearest(found, 0.2, 0.05).x, 0.2, 0.5 * grid.pixel_width());
}

TEST(TouchDetection, ABlobBelowTheMinimumAreaIsIgnored) {
  const PixelGrid grid(64, 1.0);
  // r = 0.03 R: an area of 0.0028 R^2, under the default minimum of 0.005 R^2.
  const Eigen::VectorXd image =
      draw(grid, {touch_circle(-0.4, 0.0, 0.2, 0.8), touch_circle(0.5, 0.3, 0.03, 0.8)});
  const std::vector<Touch> found = find_touches(image, grid, 0.5);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].x, -0.4, 0.02);
  TouchOptions keep_all;
  keep_all.min_area = 0;
  EXPECT_EQ(find_touches(image, grid, 0.5, keep_all).size(), 2u) << "the minimum area dropped it";
  // Nothing positive, nothing touched.
  EXPECT_TRUE(find_touches(-image, grid, 0.5).empty());
  EXPECT_TRUE(find_touches(Eigen::VectorXd::Zero(grid.num_pixels()), grid, 0.5).empty());
}

// The press's centroid (pyEIT's rule): one touch for the whole image, at the intensity-weighted
// centroid of every pixel at or above the threshold, whichever blob it lies in. Two discs of
// different intensities: the strongest blob is the brighter disc, the centroid lies between them
// where the pixel counts and intensities put it (worked out from the drawn pixels, not by the
// detector's own sums), and a small spike the blob rule drops still pulls it.
TEST(TouchDetection, ThePressCentroidWeighsEveryPixelAboveTheThreshold) {
  const PixelGrid grid(64, 1.0);
  const Eigen::VectorXd image =
      draw(grid, {touch_circle(-0.4, 0.0, 0.2, 0.8), touch_circle(0.4, 0.2, 0.15, 0.6)});
  const std::vector<Touch> blob = find_touches(image, grid, 0.5);
  ASSERT_EQ(blob.size(), 2u);
  EXPECT_NEAR(located_press(blob, {0, 0}).x(), -0.4, 0.5 * grid.pixel_width());
  double w = 0, x = 0, y = 0;
  int count = 0;
  for (int i = 0; i < grid.size(); ++i)
    for (int j = 0; j < grid.size(); ++j) {
      const double v = image[i * grid.size() + j];
      if (v < 0.5 * 0.8) continue;
      w += v, x += v * grid.center(i, j).x(), y += v * grid.center(i, j).y(), ++count;
    }
  const std::vector<Touch> centroid = centroid_touch(image, grid, 0.5);
  ASSERT_EQ(centroid.size(), 1u);
  EXPECT_NEAR(centroid[0].x, x / w, 1e-12);
  EXPECT_NEAR(centroid[0].y, y / w, 1e-12);
  EXPECT_GT(centroid[0].x, -0.4 + 0.1);  // pulled well towards the second disc
  EXPECT_NEAR(centroid[0].r, std::sqrt(count * std::pow(grid.pixel_width(), 2) / M_PI), 1e-12);
  EXPECT_NEAR(centroid[0].contrast, 0.8, 1e-9);
  // Below the blob rule's minimum area, a spike is dropped there, and counted here.
  const Eigen::VectorXd spiked =
      draw(grid, {touch_circle(-0.4, 0.0, 0.2, 0.8), touch_circle(0.6, 0.3, 0.03, 0.8)});
  EXPECT_NEAR(located_press(find_touches(spiked, grid, 0.5), {0, 0}).x(), -0.4, 0.02);
  EXPECT_GT(centroid_touch(spiked, grid, 0.5)[0].x, -0.4 + 0.01);
  EXPECT_TRUE(centroid_touch(-image, grid, 0.5).empty());
  EXPECT_EQ(testing::input_error_at([&] { centroid_touch(image, grid, 0); }),
            "centroid_touch.threshold");
}

// The rule is chosen on labelled presses: clean discs at the presses leave both rules exact and
// the tie to the blob; a brighter spot of 0.007 R^2 at the rim beside each press wins the blob
// rule (which then misses the press), and the centroid, pulled only part of the way, is chosen.
TEST(PressRule, TheRuleWithTheLowerMeanErrorOnThePressesIsChosen) {
  const PixelGrid grid(64, 1.0);
  const std::vector<std::pair<double, double>> at = {{-0.3, 0.1}, {0.2, -0.3}, {0.1, 0.35}};
  std::vector<std::vector<PressTouch>> truth;
  SampleMatrix clean(3, grid.num_pixels()), spiked(3, grid.num_pixels());
  for (int k = 0; k < 3; ++k) {
    const auto [x, y] = at[static_cast<std::size_t>(k)];
    truth.push_back({{x, y, NAN}});
    clean.row(k) = draw(grid, {touch_circle(x, y, 0.25, 0.6)}).transpose();
    spiked.row(k) = draw(grid, {touch_circle(x, y, 0.25, 0.6), touch_circle(0.85, 0.0, 0.048, 0.9)})
                        .transpose();
  }
  const PressRule plain = choose_press_rule(clean, grid, truth);
  EXPECT_FALSE(plain.centroid);
  EXPECT_EQ(plain.threshold, TouchOptions().thresholds.front());
  const PressRule rule = choose_press_rule(spiked, grid, truth);
  EXPECT_TRUE(rule.centroid);
  const PressScores blob = score_presses(press_touches(spiked, grid, {false, 0.5}), truth);
  const PressScores centroid = score_presses(press_touches(spiked, grid, rule), truth);
  EXPECT_GT(blob.mean, 0.5);  // the spot, not the press
  EXPECT_LT(centroid.mean, blob.mean);
}

TEST(TouchMatching, MissedAndPhantomTouchesAreCounted) {
  const double R = 2.0;
  const std::vector<Touch> truth = {{-0.8, 0.4, 0.3, 0.8}, {0.7, -0.6, 0.4, 0.6}};
  // One found near the first (0.1 away, 0.05 too large), one far from both (> 0.3 R = 0.6).
  const std::vector<Touch> found = {{-0.8, 0.5, 0.35, 0.5}, {0.6, 1.0, 0.2, 0.5}};
  const FrameMatch m = match_touches(found, truth, R);
  EXPECT_TRUE(m.count_correct()) << "two found for two true, though one is wrong";
  ASSERT_EQ(m.pairs.size(), 1u);
  EXPECT_EQ(m.pairs[0], std::make_pair(0, 0));
  EXPECT_EQ(m.missed(), 1);
  EXPECT_EQ(m.phantom(), 1);
  EXPECT_NEAR(m.centre_errors[0], 0.1 / R, 1e-12);
  EXPECT_NEAR(m.radius_errors[0], 0.05 / R, 1e-12);
  // Nothing found: every true touch missed; nothing true: every found one a phantom.
  EXPECT_EQ(match_touches({}, truth, R).missed(), 2);
  EXPECT_FALSE(match_touches({}, truth, R).count_correct());
  EXPECT_EQ(match_touches(found, {}, R).phantom(), 2);
}

TEST(TouchMatching, TheExactAssignmentBeatsGreedyNearestMatching) {
  // Distances: t0-f0 0.09 (the nearest pair of all), t0-f1 0.15, t1-f0 0.11, t1-f1 0.35.
  // Greedy takes t0-f0 and is left with t1-f1, beyond the 0.3 R gate: one pair. The exact
  // matching pairs t0-f1 and t1-f0: two pairs, 0.26 in all.
  const std::vector<Touch> truth = {{0.0, 0.0, 0.1, 0.5}, {0.2, 0.0, 0.1, 0.5}};
  const std::vector<Touch> found = {{0.09, 0.0, 0.1, 0.5}, {-0.15, 0.0, 0.1, 0.5}};
  const FrameMatch m = match_touches(found, truth, 1.0);
  ASSERT_EQ(m.pairs.size(), 2u);
  EXPECT_EQ(m.pairs[0], std::make_pair(0, 1));
  EXPECT_EQ(m.pairs[1], std::make_pair(1, 0));
  EXPECT_NEAR(m.centre_errors[0] + m.centre_errors[1], 0.26, 1e-12);
  EXPECT_EQ(m.missed() + m.phantom(), 0);
  // With a gate wide enough for greedy's pairs too, the least total distance still wins: 0.26,
  // not greedy's 0.09 + 0.35 = 0.44.
  TouchOptions wide;
  wide.gate = 1.0;
  const FrameMatch w = match_touches(found, truth, 1.0, wide);
  EXPECT_EQ(w.pairs[0], std::make_pair(0, 1));
  EXPECT_NEAR(w.centre_errors[0] + w.centre_errors[1], 0.26, 1e-12);
}

TEST(TouchSummary, MediansAndPercentilesOfKnownNumbers) {
  FrameMatch a, b, c;
  a.found = 2, a.truth = 2, a.pairs = {{0, 0}, {1, 1}};
  a.centre_errors = {0.1, 0.4}, a.radius_errors = {0.02, 0.01};
  b.found = 4, b.truth = 3, b.pairs = {{0, 1}, {1, 0}, {2, 3}};
  b.centre_errors = {0.3, 0.2, 0.5}, b.radius_errors = {0.03, 0.04, 0.05};
  c.found = 0, c.truth = 1;  // missed
  const TouchScores s = summarize_touches({a, b, c});
  EXPECT_EQ(s.frames, 3);
  EXPECT_NEAR(s.count_accuracy, 1.0 / 3, 1e-15);
  // Errors 0.1 0.2 0.3 0.4 0.5: median 0.3; p90 at rank 3.6, 0.4 + 0.6 x 0.1.
  EXPECT_NEAR(s.centre_error_median, 0.3, 1e-15);
  EXPECT_NEAR(s.centre_error_p90, 0.46, 1e-15);
  EXPECT_NEAR(s.radius_error_median, 0.03, 1e-15);
  EXPECT_NEAR(s.missed_per_frame, 1.0 / 3, 1e-15);   // c's one
  EXPECT_NEAR(s.phantom_per_frame, 1.0 / 3, 1e-15);  // b's fourth
  EXPECT_EQ(s.true_touches, 6);
  EXPECT_EQ(s.matched, 5);
  ASSERT_EQ(s.centre_error_quantiles.size(), 21u);
  EXPECT_NEAR(s.centre_error_quantiles.front(), 0.1, 1e-15);
  EXPECT_NEAR(s.centre_error_quantiles[10], 0.3, 1e-15);
  EXPECT_NEAR(s.centre_error_quantiles.back(), 0.5, 1e-15);
  // By true count: 1 (c), 2 (a), 3 (b).
  ASSERT_EQ(s.by_count.size(), 3u);
  EXPECT_EQ(s.by_count[0].touches, 1);
  EXPECT_TRUE(std::isnan(s.by_count[0].centre_error_median));
  EXPECT_EQ(s.by_count[1].count_accuracy, 1.0);
  EXPECT_NEAR(s.by_count[1].centre_error_median, 0.25, 1e-15);
  EXPECT_EQ(s.by_count[2].count_accuracy, 0.0);
  EXPECT_NEAR(s.by_count[2].centre_error_median, 0.3, 1e-15);
  // No frames: not scored.
  EXPECT_EQ(summarize_touches({}).frames, 0);
  // Signals unknown: no visibility figures.
  EXPECT_TRUE(s.by_signal.empty());
  EXPECT_EQ(s.visible_frames, 0);
}

// With the true touches' signals: a frame counts as visible only when every touch carries at least
// 5 %, and each true touch is binned by its signal, found when matched.
TEST(TouchSummary, VisibleFramesAndTouchesFoundBySignal) {
  FrameMatch a, b, c;
  a.found = 2, a.truth = 2, a.pairs = {{0, 0}, {1, 1}}, a.centre_errors = {0.1, 0.1};
  a.truth_signals = {0.9, 0.06};  // visible, counted right
  b.found = 1, b.truth = 2, b.pairs = {{0, 0}}, b.centre_errors = {0.1};
  b.truth_signals = {0.97, 0.01};  // the faint one missed: not visible
  c.found = 2, c.truth = 2, c.pairs = {{1, 0}}, c.centre_errors = {0.2};
  c.truth_signals = {0.05, 0.03};  // 0.05 missed (with a phantom), 0.03: not visible
  TouchScores s = summarize_touches({a, b, c});
  EXPECT_EQ(s.visible_frames, 1);
  EXPECT_EQ(s.visible_count_accuracy, 1.0);
  EXPECT_NEAR(s.count_accuracy, 2.0 / 3, 1e-15);  // a and c count right
  ASSERT_EQ(s.by_signal.size(), 3u);
  EXPECT_EQ(s.by_signal[0].from, 0.0);
  EXPECT_EQ(s.by_signal[0].to, 0.02);
  EXPECT_EQ(s.by_signal[0].touches, 1);  // b's 0.01
  EXPECT_EQ(s.by_signal[0].found, 0);
  EXPECT_EQ(s.by_signal[1].touches, 1);  // c's 0.03, matched
  EXPECT_EQ(s.by_signal[1].found, 1);
  EXPECT_EQ(s.by_signal[2].from, 0.05);
  EXPECT_TRUE(std::isinf(s.by_signal[2].to));
  EXPECT_EQ(s.by_signal[2].touches, 4);  // 0.9, 0.06, 0.97, 0.05 (the edge is in)
  EXPECT_EQ(s.by_signal[2].found, 3);
  // One frame's signal unknown: none reported.
  c.truth_signals[0] = NAN;
  s = summarize_touches({a, b, c});
  EXPECT_TRUE(s.by_signal.empty());
  EXPECT_TRUE(std::isnan(s.visible_count_accuracy));
}

// Two validation frames built so that each candidate threshold fails in a known way:
//   frame 0: a touch with a faint shoulder (0.45 of the peak), a faint true touch (0.55) and a
//            phantom blob (0.35) that is no touch;
//   frame 1: a touch with a shoulder at 0.47 of its peak.
// 0.3 sees the phantom (3 found for 2), 0.6 and 0.7 lose the faint touch (1 for 2): frame 0 wrong.
// 0.4 and 0.5 count both frames right, but 0.4 takes in the shoulders, which pull the centres off.
TEST(TouchThreshold, TheChoiceIsTheRuleThatIsBestOnValidation) {
  const PixelGrid grid(64, 1.0);
  const Circle a = touch_circle(-0.4, 0.3, 0.15, 1.0), faint = touch_circle(0.4, -0.4, 0.15, 0.55),
               b = touch_circle(0.1, -0.1, 0.2, 0.9);
  const Eigen::VectorXd frame0 = draw(grid, {a, faint, touch_circle(0.3, 0.5, 0.12, 0.35)})
                                     .cwiseMax(draw(grid, {touch_circle(-0.22, 0.3, 0.12, 0.45)}));
  const Eigen::VectorXd frame1 =
      draw(grid, {b}).cwiseMax(draw(grid, {touch_circle(0.32, -0.1, 0.12, 0.42)}));
  SampleMatrix images(2, grid.num_pixels());
  images.row(0) = frame0.transpose(), images.row(1) = frame1.transpose();
  const TouchFrames truth = touches_of({{a, faint}, {b}}, kBackground);

  const ThresholdChoice choice = choose_touch_threshold(images, truth, grid);
  ASSERT_EQ(choice.scores.size(), 5u);
  const std::vector<double> accuracy = {0.5, 1, 1, 0.5, 0.5};
  for (std::size_t k = 0; k < 5; ++k)
    EXPECT_EQ(choice.scores[k].count_accuracy, accuracy[k]) << choice.scores[k].threshold;
  EXPECT_GT(choice.scores[1].centre_error_median, 2 * choice.scores[2].centre_error_median);
  EXPECT_EQ(choice.threshold, 0.5);
  // Between 0.3 and 0.6 alone, both miscount frame 0: the tie goes by the median centre error,
  // and 0.3 takes in the shoulders while 0.6 does not.
  TouchOptions others;
  others.thresholds = {0.3, 0.6};
  const ThresholdChoice tie = choose_touch_threshold(images, truth, grid, others);
  EXPECT_EQ(tie.scores[0].count_accuracy, tie.scores[1].count_accuracy);
  EXPECT_EQ(tie.threshold, 0.6);
  // The test images are scored at the validation's choice.
  const TouchScores test = score_touch_images(images, truth, images, truth, grid);
  EXPECT_EQ(test.threshold, 0.5);
  EXPECT_EQ(test.count_accuracy, 1.0);
}

TEST(TouchOptions, BadValuesNameTheField) {
  using testing::input_error_at;
  const PixelGrid grid(8, 1.0);
  const Eigen::VectorXd image = Eigen::VectorXd::Ones(grid.num_pixels());
  TouchOptions o;
  o.gate = 0;
  EXPECT_EQ(input_error_at([&] { match_touches({}, {}, 1.0, o); }), "TouchOptions.gate");
  o = {}, o.min_area = -1;
  EXPECT_EQ(input_error_at([&] { find_touches(image, grid, 0.5, o); }), "TouchOptions.min_area");
  o = {}, o.thresholds = {0.5, 1.5};
  EXPECT_EQ(input_error_at([&] { choose_touch_threshold({}, {}, grid, o); }),
            "TouchOptions.thresholds");
  EXPECT_EQ(input_error_at([&] { find_touches(image, grid, 0); }), "find_touches.threshold");
  EXPECT_EQ(input_error_at([&] { find_touches(Eigen::VectorXd::Ones(3), grid, 0.5); }),
            "find_touches.image");
  EXPECT_EQ(input_error_at([&] { score_touches({{}}, {}, 1.0); }), "score_touches.found");
  EXPECT_EQ(input_error_at([&] { touches_of(std::vector<Circle>{}, 0.0); }),
            "touches_of.background");
}

ResultRow touch_row(const std::string& method, const std::string& augment, double snr, double cc,
                    double count, double centre) {
  ResultRow r;
  r.method = method, r.augment = augment, r.snr_db = snr, r.cc = cc, r.re = 0.5, r.frames = 4;
  r.latency_median_ms = 1;
  r.touch.frames = 4, r.touch.threshold = 0.5, r.touch.count_accuracy = count;
  r.touch.centre_error_median = centre, r.touch.centre_error_p90 = 2 * centre;
  r.touch.radius_error_median = 0.02, r.touch.missed_per_frame = 0.25;
  r.touch.phantom_per_frame = 0.5, r.touch.true_touches = 16, r.touch.matched = 12;
  for (int k = 0; k <= 20; ++k) r.touch.centre_error_quantiles.push_back(centre * k / 10.0);
  r.touch.by_count = {{4, 4, count, centre}};
  return r;
}

TEST(TouchResults, JsonRoundTripAndOlderFilesWithoutThem) {
  RunResults r;
  r.program = "eitbench test";
  ResultRow scored = touch_row("tv", "-", INFINITY, 0.8, 0.75, 0.04);
  scored.touch.centre_error_p90 = NAN;  // stored as null
  ResultRow plain = scored;
  plain.method = "noser", plain.touch = TouchScores{};  // not scored
  r.rows = {scored, plain};
  r.recommendation = "Pick tv";
  const std::string path = (fs::temp_directory_path() / "eitbench_touch_roundtrip.json").string();
  write_results_json(path, r);
  const RunResults back = read_results_json(path);
  ASSERT_EQ(back.rows.size(), 2u);
  const TouchScores& t = back.rows[0].touch;
  EXPECT_EQ(t.frames, 4);
  EXPECT_EQ(t.threshold, 0.5);
  EXPECT_EQ(t.count_accuracy, 0.75);
  EXPECT_EQ(t.centre_error_median, 0.04);
  EXPECT_TRUE(std::isnan(t.centre_error_p90));
  EXPECT_EQ(t.radius_error_median, 0.02);
  EXPECT_EQ(t.missed_per_frame, 0.25);
  EXPECT_EQ(t.phantom_per_frame, 0.5);
  EXPECT_EQ(t.true_touches, 16);
  EXPECT_EQ(t.matched, 12);
  EXPECT_EQ(t.centre_error_quantiles, scored.touch.centre_error_quantiles);
  ASSERT_EQ(t.by_count.size(), 1u);
  EXPECT_EQ(t.by_count[0].touches, 4);
  EXPECT_EQ(t.by_count[0].centre_error_median, 0.04);
  EXPECT_EQ(back.rows[1].touch.frames, 0);
  EXPECT_TRUE(t.by_signal.empty());  // none written, none read

  // The visibility figures, where known, come back.
  r.rows[0].touch.visible_frames = 3, r.rows[0].touch.visible_count_accuracy = 2.0 / 3;
  r.rows[0].touch.model_error_median = 0.036;
  r.rows[0].touch.by_signal = {{0, 0.02, 2, 0}, {0.02, 0.05, 3, 1}, {0.05, INFINITY, 11, 11}};
  write_results_json(path, r);
  const TouchScores v = read_results_json(path).rows[0].touch;
  EXPECT_EQ(v.visible_frames, 3);
  EXPECT_EQ(v.visible_count_accuracy, 2.0 / 3);
  EXPECT_EQ(v.model_error_median, 0.036);
  ASSERT_EQ(v.by_signal.size(), 3u);
  EXPECT_TRUE(std::isinf(v.by_signal[2].to));
  EXPECT_EQ(v.by_signal[1].from, 0.02);
  EXPECT_EQ(v.by_signal[1].touches, 3);
  EXPECT_EQ(v.by_signal[1].found, 1);

  // A results.json from before the touch metrics: its rows have no "touch", and read as unscored.
  std::ifstream in(path);
  nlohmann::json doc = nlohmann::json::parse(in);
  for (auto& row : doc.at("results")) row.erase("touch");
  fs::remove(path);
  const RunResults old = parse_results_json(doc.dump(), "old.json");
  ASSERT_EQ(old.rows.size(), 2u);
  EXPECT_EQ(old.rows[0].touch.frames, 0);
  EXPECT_EQ(old.rows[0].cc, 0.8);
  EXPECT_FALSE(has_touch_scores(old.rows));
  // A mistyped touch field is an error naming the file.
  doc.at("results")[0]["touch"] = {{"frames", "four"}};
  EXPECT_EQ(testing::input_error_at([&] { parse_results_json(doc.dump(), "bad.json"); }),
            "bad.json.results");
}

TEST(TouchReport, TheTableAndTheBestMethodByEachMeasure) {
  RunResults r;
  r.program = "eitbench test";
  r.rows = {touch_row("tikhonov", "-", INFINITY, 0.75, 0.5, 0.03),
            touch_row("tikhonov", "-", 40, 0.7, 0.5, 0.05),
            touch_row("tv", "-", INFINITY, 0.8, 0.75, 0.06),
            touch_row("tv", "-", 40, 0.8, 0.75, 0.06),
            touch_row("dnn", "d16", INFINITY, 0.86, 1.0, 0.03),
            touch_row("dnn", "d16", 40, 0.85, 0.75, 0.07)};
  r.rows[3].touch.threshold = 0.4;
  // At 40 dB (the pick's SNR): centre best tikhonov, count tied tv and dnn, CC dnn.
  const std::string ranking = touch_ranking(r.rows, headline_snr(r.rows));
  EXPECT_EQ(ranking,
            "At 40 dB, the best median centre error: tikhonov (0.050 R); the best count accuracy: "
            "tv, dnn (d16) (75 %); the best CC: dnn (d16) (0.850).");
  const std::string path = (fs::temp_directory_path() / "eitbench_touch_report.md").string();
  write_report(path, r);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fs::remove(path);
  EXPECT_NE(text.find("## Touches"), std::string::npos);
  EXPECT_NE(text.find("| tv | 0.4 | 75 % | 0.060 | 0.120 | 0.020 | 0.25 | 0.50 |"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find(ranking), std::string::npos);
  // The per-SNR table: count then centre, noise-free first.
  EXPECT_NE(text.find("| dnn (d16) | 100 % | 75 % | 0.030 | 0.070 |"), std::string::npos) << text;
  EXPECT_NE(text.find("touch_centre_errors.png"), std::string::npos);
  EXPECT_EQ(text.find("every touch visible"), std::string::npos);  // signals unknown
  // With the touches' signals: the visible frames' column and the table by signal.
  for (auto& row : r.rows) {
    row.touch.visible_frames = 2, row.touch.visible_count_accuracy = 1.0;
    row.touch.model_error_median = 0.036;
    row.touch.by_signal = {{0, 0.02, 2, 0}, {0.02, 0.05, 4, 1}, {0.05, INFINITY, 10, 9}};
  }
  write_report(path, r);
  std::ifstream seen(path);
  const std::string visible((std::istreambuf_iterator<char>(seen)),
                            std::istreambuf_iterator<char>());
  fs::remove(path);
  EXPECT_NE(visible.find("| tv | 0.4 | 75 % | 100 % | 0.060 |"), std::string::npos) << visible;
  EXPECT_NE(visible.find("its misfit is 3.6 % of a noise-free test frame"), std::string::npos);
  EXPECT_NE(visible.find("2 of 4 test frames have every touch visible (≥ 5 %)"), std::string::npos);
  EXPECT_NE(visible.find("| method | < 2 % (2) | 2 – 5 % (4) | ≥ 5 % (10) |"), std::string::npos);
  EXPECT_NE(visible.find("| tv | 0 % | 25 % | 90 % |"), std::string::npos) << visible;
  // Without touch scores, no section.
  for (auto& row : r.rows) row.touch = TouchScores{};
  write_report(path, r);
  std::ifstream again(path);
  const std::string plain((std::istreambuf_iterator<char>(again)),
                          std::istreambuf_iterator<char>());
  fs::remove(path);
  EXPECT_EQ(plain.find("## Touches"), std::string::npos);
}

}  // namespace
}  // namespace eitbench
