#include "eitbench/bench/report/microbench.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/significance.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {

using json = nlohmann::json;

namespace {

double unit_in_ns(const std::string& unit, const std::string& source, const std::string& field) {
  if (unit == "ns") return 1;
  if (unit == "us") return 1e3;
  if (unit == "ms") return 1e6;
  if (unit == "s") return 1e9;
  throw InputError(source, field, "unknown time unit '" + unit + "' (ns, us, ms, s)");
}

// A time in the unit that keeps three figures readable.
std::string format_ns(double ns) {
  if (!std::isfinite(ns)) return "-";
  if (ns >= 1e9) return fmt::format("{:.3g} s", ns / 1e9);
  if (ns >= 1e6) return fmt::format("{:.3g} ms", ns / 1e6);
  if (ns >= 1e3) return fmt::format("{:.3g} us", ns / 1e3);
  return fmt::format("{:.3g} ns", ns);
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

json read_json_file(const std::string& path) {
  try {
    return json::parse(read_file_bytes(path, 1LL << 30));
  } catch (const json::exception& e) {
    throw InputError(path, "", std::string("not JSON: ") + e.what());
  }
}

bool is_microbench_json(const json& doc) {
  return doc.is_object() && doc.contains("benchmarks") && doc["benchmarks"].is_array() &&
         doc.contains("context") && doc["context"].is_object();
}

MicrobenchRun parse_microbench_json(const json& doc, const std::string& source) {
  if (!is_microbench_json(doc))
    throw InputError(source, "benchmarks",
                     "not Google Benchmark JSON (no \"benchmarks\" array and \"context\" object)");
  MicrobenchRun run;
  for (const auto& [key, value] : doc["context"].items())
    if (value.is_primitive())
      run.context[key] = value.is_string() ? value.get<std::string>() : value.dump();
  std::map<std::string, std::size_t> index;
  const json& list = doc["benchmarks"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const json& b = list[i];
    const std::string at = fmt::format("benchmarks[{}]", i);
    if (!b.is_object()) throw InputError(source, at, "is not an object");
    if (b.value("run_type", "iteration") != "iteration" || b.value("error_occurred", false))
      continue;
    std::string field = at + ".name";
    try {
      const std::string name = b.contains("run_name") ? b.at("run_name").get<std::string>()
                                                      : b.at("name").get<std::string>();
      field = at + ".time_unit";
      const double unit = unit_in_ns(b.value("time_unit", "ns"), source, field);
      field = at + ".real_time";
      const double real = b.at("real_time").get<double>() * unit;
      field = at + ".cpu_time";
      const double cpu = b.at("cpu_time").get<double>() * unit;
      if (!(std::isfinite(real) && real >= 0 && std::isfinite(cpu) && cpu >= 0))
        throw InputError(source, field, "times must be finite and not negative");
      auto [it, fresh] = index.emplace(name, run.series.size());
      if (fresh) run.series.push_back({name, {}, {}});
      run.series[it->second].real_ns.push_back(real);
      run.series[it->second].cpu_ns.push_back(cpu);
    } catch (const json::exception& e) {
      throw InputError(source, field, std::string("missing or not a number: ") + e.what());
    }
  }
  if (run.series.empty())
    throw InputError(source, "benchmarks", "holds no benchmark repetition (only aggregates?)");
  return run;
}

MicrobenchRun read_microbench_json(const std::string& path) {
  return parse_microbench_json(read_json_file(path), path);
}

Comparison compare_microbench(const MicrobenchRun& old_run, const MicrobenchRun& new_run,
                              const SpeedOptions& o) {
  Comparison c;
  const char* clock = o.cpu_time ? "CPU" : "wall";
  c.table.push_back({"benchmark", fmt::format("old ({} median)", clock), "new", "change",
                     "repetitions", "p (Mann-Whitney)", "verdict"});
  std::map<std::string, const MicrobenchSeries*> fresh;
  for (const auto& s : new_run.series) fresh[s.name] = &s;
  for (const auto& old : old_run.series) {
    const auto it = fresh.find(old.name);
    const auto& a = o.cpu_time ? old.cpu_ns : old.real_ns;
    if (it == fresh.end()) {
      c.table.push_back(
          {old.name, format_ns(median(a)), "-", "-", fmt::format("{}", a.size()), "-", "MISSING"});
      c.regressions.push_back(old.name + ": missing from the new run");
      continue;
    }
    const auto& b = o.cpu_time ? it->second->cpu_ns : it->second->real_ns;
    const double ma = median(a), mb = median(b), change = ma > 0 ? mb / ma - 1 : 0;
    const TestResult t = mann_whitney_u(a, b);
    const int n = static_cast<int>(std::min(a.size(), b.size()));
    std::string verdict;
    if (n < o.min_repetitions)
      verdict = fmt::format("undecided: {} repetitions, need {}", n, o.min_repetitions);
    else if (t.p_value >= o.alpha || std::abs(change) <= o.min_change)
      verdict = "same";
    else
      verdict = change > 0 ? "SLOWER" : "faster";
    if (verdict == "SLOWER")
      c.regressions.push_back(fmt::format("{}: {} -> {} ({:+.1f} %, p = {:.2g})", old.name,
                                          format_ns(ma), format_ns(mb), 100 * change, t.p_value));
    c.table.push_back(
        {old.name, format_ns(ma), format_ns(mb), fmt::format("{:+.1f} %", 100 * change),
         fmt::format("{} / {}", a.size(), b.size()), fmt::format("{:.2g}", t.p_value), verdict});
  }
  return c;
}

}  // namespace eitbench
