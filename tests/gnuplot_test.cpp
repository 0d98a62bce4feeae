// The line plots by gnuplot: each figure's data and script beside it, drawn whole or not at all,
// one colour per method in every figure, and a report without gnuplot or with a failing one.
#include "eitbench/bench/report/gnuplot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "cli_fixture.h"

namespace eitbench {
namespace {

LinePlot efficiency_like() {
  LinePlot plot;
  plot.title = "test CC against training-set size";
  plot.x_label = "training frames";
  plot.y_label = "CC";
  plot.log_x = true;
  PlotSeries none, d16;
  none.label = "none", none.key = "dnn (none)", none.points = true;
  none.x = {0, 250, 500, 1000}, none.y = {0.1, 0.70, 0.75, 0.80};  // x = 0 has no place on log x
  none.low = {0.1, 0.69, 0.74, 0.79}, none.high = {0.1, 0.71, 0.76, 0.81};
  d16.label = "d16, none's steps", d16.key = "dnn (d16)", d16.dashed = true;
  d16.x = {250, 500, 1000}, d16.y = {0.78, 0.82, 0.86};
  plot.series = {none, d16};
  return plot;
}

class Gnuplot : public Cli {};

TEST_F(Gnuplot, DataAndScriptBesideTheFigure) {
  const bool drawn = write_plot(efficiency_like(), path("efficiency.png"));
  const std::string data = file_text(path("efficiency.dat")),
                    script = file_text(path("efficiency.gp"));
  // Two blocks (gnuplot's index 0 and 1); the point at x = 0 is left out on the log axis.
  EXPECT_NE(data.find("# none\n250 0.7 0.69 0.71\n500"), std::string::npos) << data;
  EXPECT_EQ(data.find("\n0 0.1"), std::string::npos) << data;
  EXPECT_NE(data.find("\n\n\n# d16, none's steps\n250 0.78\n"), std::string::npos) << data;
  EXPECT_NE(script.find("set logscale x"), std::string::npos) << script;
  EXPECT_NE(script.find("index 0 using 1:2:3:4 with yerrorbars"), std::string::npos) << script;
  EXPECT_NE(script.find("lc rgb '" + series_colour("dnn (d16)") + "' lw 2 dt 2"), std::string::npos)
      << script;
  EXPECT_NE(script.find("set output 'efficiency.svg'"), std::string::npos) << script;
  ASSERT_EQ(drawn, !gnuplot_program().empty());
  if (!drawn) GTEST_SKIP() << "no gnuplot here: data and script checked, drawing not";
  const std::string png = file_text(path("efficiency.png"));
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_NE(file_text(path("efficiency.svg")).find("<svg"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(dir_))  // the drawing folder is gone
    EXPECT_EQ(entry.path().filename().string().find(".gnuplot"), std::string::npos) << entry.path();
}

TEST(SeriesColour, OneColourPerMethodAndTheyDiffer) {
  EXPECT_EQ(series_colour("dnn (d16)"), series_colour("dnn (d16)"));
  std::set<std::string> seen;
  for (const char* method : {"tikhonov", "noser", "laplace", "smooth", "greit", "gn", "tv", "shape",
                             "shape-linear", "dnn (none)", "dnn (d16)", "dnn (paper)"})
    EXPECT_TRUE(seen.insert(series_colour(method)).second) << method << " shares a colour";
}

}  // namespace
}  // namespace eitbench
