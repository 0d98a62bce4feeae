// eitbench history: entries appended at commits, each metric over the commits with its significant
// changes marked (Welch's z for the runs' means, Mann-Whitney for microbenchmark repetitions), the
// figures' files, and a history file that is not one refused naming its line.
#include <fstream>

#include "cli_fixture.h"
#include "eitbench/bench/report/history.h"

namespace eitbench {
namespace {

RunResults run_with(double noser_cc, double tv_latency_ms) {
  RunResults r;
  r.program = "eitbench test";
  r.machine["cpu"] = "test cpu";
  r.recommendation = "none";
  for (const char* method : {"noser", "tv"}) {
    ResultRow row;
    row.method = method, row.snr_db = INFINITY, row.frames = 229;
    row.cc = method == std::string("noser") ? noser_cc : 0.83, row.cc_std = 0.08;
    row.re = 0.9, row.re_std = 0.1;
    row.latency_median_ms = method == std::string("tv") ? tv_latency_ms : 0.07;
    r.rows.push_back(row);
  }
  return r;
}

// CC falls by 0.05 at a spread of 0.08 over 229 frames (z = 6.7): marked; by 0.005 (z = 0.7):
// not; tv three times slower: marked.
TEST(History, SeriesMarkSignificantChangesOnly) {
  std::vector<HistoryEntry> h = {history_entry(run_with(0.78, 70), "c1", "d", "a.json"),
                                 history_entry(run_with(0.775, 70), "c2", "d", "b.json"),
                                 history_entry(run_with(0.725, 210), "c3", "d", "c.json")};
  const auto series = history_series(h, {});
  auto find = [&](const std::string& name, const std::string& metric) {
    for (const auto& s : series)
      if (s.name == name && s.metric == metric) return s;
    ADD_FAILURE() << name << " " << metric;
    return HistorySeries{};
  };
  const HistorySeries cc = find("noser/-/inf", "cc");
  ASSERT_EQ(cc.points.size(), 3u);
  EXPECT_FALSE(cc.points[0].changed);
  EXPECT_FALSE(cc.points[1].changed);
  EXPECT_GT(cc.points[1].p_value, 0.05);
  EXPECT_TRUE(cc.points[2].changed);
  EXPECT_LT(cc.points[2].p_value, 1e-6);
  EXPECT_FALSE(find("tv/-/inf", "cc").points[2].changed);
  EXPECT_TRUE(find("tv/-/inf", "latency_ms").points[2].changed);
  EXPECT_FALSE(find("noser/-/inf", "latency_ms").points[2].changed);

  const LinePlot plot = history_plot(h, series, "run", "cc");
  ASSERT_EQ(plot.series.size(), 3u);  // noser, tv, the marks
  EXPECT_EQ(plot.x_tick_labels, (std::vector<std::string>{"c1", "c2", "c3"}));
  EXPECT_EQ(plot.series[2].x, std::vector<double>{2.0});
}

class HistoryCli : public Cli {};

TEST_F(HistoryCli, AddsShowsAndRefuses) {
  const std::string h = " --history " + path("h.jsonl");
  write_results_json(path("one.json"), run_with(0.78, 70));
  write_results_json(path("two.json"), run_with(0.72, 70));
  EXPECT_EQ(run("history add " + path("one.json") + " --commit 1111aaaa" + h).exit_code, 0);
  EXPECT_EQ(run("history add " + path("two.json") + " --commit 2222bbbb" + h).exit_code, 0);
  // Microbenchmark JSON with nine repetitions each: 1 ms, then 1.3 ms, at the same two commits.
  for (const auto& [name, ms] :
       {std::pair<std::string, double>{"m1.json", 1.0}, {"m2.json", 1.3}}) {
    std::ofstream out(path(name));
    out << R"({"context": {"host_name": "t"}, "benchmarks": [)";
    for (int k = 0; k < 9; ++k)
      out << (k ? "," : "") << R"({"name": "BM_X", "run_type": "iteration", "time_unit": "ms", )"
          << "\"real_time\": " << ms * (1 + 0.001 * k) << ", \"cpu_time\": " << ms << "}";
    out << "]}";
  }
  EXPECT_EQ(run("history add " + path("m1.json") + " --commit 1111aaaa" + h).exit_code, 0);
  EXPECT_EQ(run("history add " + path("m2.json") + " --commit 2222bbbb" + h).exit_code, 0);

  const Result shown = run("history show --out " + path("figures") + h);
  ASSERT_EQ(shown.exit_code, 0) << shown.output;
  EXPECT_NE(shown.output.find("0.72*"), std::string::npos) << shown.output;   // noser's CC
  EXPECT_NE(shown.output.find("1.305*"), std::string::npos) << shown.output;  // BM_X, median
  EXPECT_EQ(shown.output.find("0.83*"), std::string::npos) << shown.output;   // tv: unchanged
  for (const char* figure : {"history_cc", "history_re", "history_latency", "history_microbench"})
    for (const char* ext : {".dat", ".gp"})
      EXPECT_TRUE(fs::exists(path("figures") + "/" + figure + ext)) << figure << ext;

  // The same commit and kind again: refused, the history unchanged; --replace replaces.
  const Result twice = run("history add " + path("two.json") + " --commit 2222bbbb" + h);
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.output.find("--replace"), std::string::npos) << twice.output;
  EXPECT_EQ(read_history(path("h.jsonl")).size(), 4u);
  EXPECT_EQ(run("history add " + path("one.json") + " --commit 2222bbbb --replace" + h).exit_code,
            0);
  EXPECT_EQ(read_history(path("h.jsonl")).size(), 4u);
  EXPECT_EQ(run("history show" + h).output.find("0.72*"), std::string::npos);

  EXPECT_EQ(run("history add " + path("one.json") + " --commit 'two words'" + h).exit_code, 2);
  { std::ofstream(path("h.jsonl"), std::ios::app) << "{\"commit\": 3}\n"; }
  const Result broken = run("history show" + h);
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.output.find("h.jsonl: line 5"), std::string::npos) << broken.output;
  EXPECT_EQ(run("history show --history " + path("none.jsonl")).exit_code, 2);
}

}  // namespace
}  // namespace eitbench
