#include "eitbench/bench/report/gnuplot.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/core.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/jacobian/error.h"

namespace eitbench {
namespace fs = std::filesystem;
namespace {

// Okabe and Ito's colour-blind-safe colours first, then others that stay apart from them.
const std::map<std::string, std::string>& method_colours() {
  static const std::map<std::string, std::string> colours = {
      {"tikhonov", "#7f7f7f"},     {"noser", "#e69f00"},
      {"laplace", "#56b4e9"},      {"greit", "#b8860b"},
      {"gn", "#cc79a7"},           {"tv", "#0072b2"},
      {"shape", "#d55e00"},        {"shape-linear", "#8c564b"},
      {"dnn (none)", "#000000"},   {"dnn (d16)", "#009e73"},
      {"dnn (paper)", "#9467bd"},  {"dnn (rotations)", "#17becf"},
      {"dnn (mirror)", "#bcbd22"}, {"significant change", "#d62728"},
      {"smooth", "#2ca02c"}};
  return colours;
}

// gnuplot's strings in double quotes: backslashes and quotes escaped.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + '"';
}

bool has_error_bars(const PlotSeries& s) {
  return !s.low.empty() && s.low.size() == s.y.size() && s.high.size() == s.y.size();
}

// One block per series (gnuplot's `index`), x y [low high] a line; a point a log axis cannot show
// is left out.
std::string data_text(const LinePlot& plot) {
  std::ostringstream out;
  out.precision(9);
  out << "# " << plot.title << "\n# x: " << plot.x_label << "; y: " << plot.y_label << "\n";
  for (const PlotSeries& s : plot.series) {
    out << "\n\n# " << s.label << "\n";
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      const double x = s.x.empty() ? static_cast<double>(i) : s.x[i];
      if ((plot.log_x && !(x > 0)) || (plot.log_y && !(s.y[i] > 0)) || !std::isfinite(s.y[i]))
        continue;
      out << x << ' ' << s.y[i];
      if (has_error_bars(s)) out << ' ' << s.low[i] << ' ' << s.high[i];
      out << '\n';
    }
  }
  return out.str();
}

// A log axis over the data's own x values, ticked at them (training-set sizes: 500, 1000, 2000),
// rather than over whole decades with one label.
std::string log_ticks(const LinePlot& plot) {
  std::set<double> xs;
  for (const PlotSeries& s : plot.series)
    for (double x : s.x)
      if (x > 0 && std::isfinite(x)) xs.insert(x);
  if (xs.empty() || xs.size() > 12) return "set mxtics 10\n";
  std::string tics;
  for (double x : xs) tics += fmt::format("{}{:g}", tics.empty() ? "" : ", ", x);
  return fmt::format("set xtics ({})\nset xrange [{:g}:{:g}]\n", tics, *xs.begin() / 1.15,
                     *xs.rbegin() * 1.15);
}

std::string script_text(const LinePlot& plot, const std::string& name, int width, int height) {
  std::ostringstream gp;
  gp << "# " << name << ".png and " << name << ".svg from " << name
     << ".dat, drawn by eitbench. Edit this script and run `gnuplot " << name
     << ".gp` in this folder to draw them again.\n"
     << "set title " << quoted(plot.title) << " noenhanced\n"
     << "set xlabel " << quoted(plot.x_label) << " noenhanced\n"
     << "set ylabel " << quoted(plot.y_label) << " noenhanced\n"
     << "set grid back lc rgb '#dddddd'\nset border 3\nset tics nomirror\n"
     << "set key outside right top noenhanced\nset format x '%g'\nset format y '%g'\n";
  if (plot.log_x) gp << "set logscale x\n" << log_ticks(plot);
  if (plot.log_y) gp << "set logscale y\nset mytics 10\n";
  if (!plot.x_tick_labels.empty()) {
    std::string tics;
    for (std::size_t k = 0; k < plot.x_tick_labels.size(); ++k)
      tics += fmt::format("{}{} {}", k ? ", " : "", quoted(plot.x_tick_labels[k]), k);
    gp << fmt::format("set xtics rotate by -30 ({})\nset xrange [-0.5:{}]\n", tics,
                      plot.x_tick_labels.size() - 0.5);
  }
  gp << "plot ";
  for (std::size_t k = 0; k < plot.series.size(); ++k) {
    const PlotSeries& s = plot.series[k];
    const std::string colour = series_colour(s.key.empty() ? s.label : s.key);
    const std::string style = fmt::format("lc rgb '{}' lw 2 dt {}", colour, s.dashed ? 2 : 1);
    gp << (k ? ", \\\n     " : "")
       << fmt::format("'{}.dat' index {} using 1:2 with {} {} title {}", name, k,
                      s.only_points ? "points pt 6 ps 2.2"
                      : s.points    ? "linespoints pt 7 ps 0.6"
                                    : "lines",
                      style, quoted(s.label));
    if (has_error_bars(s))
      gp << fmt::format(
          ", \\\n     '{}.dat' index {} using 1:2:3:4 with yerrorbars {} pt 7 "
          "ps 0.4 notitle",
          name, k, style);
  }
  gp << "\n"
     << fmt::format(
            "set terminal pngcairo size {},{} enhanced font 'DejaVu Sans,10'\n"
            "set output '{}.png'\nreplot\n"
            "set terminal svg size {},{} dynamic enhanced font 'DejaVu Sans,10'\n"
            "set output '{}.svg'\nreplot\nunset output\n",
            width, height, name, width, height, name);
  return gp.str();
}

// Runs `program script` in `folder`, its output to `log`; the exit status (or -1).
int run_in(const std::string& program, const std::string& folder, const std::string& script,
           const std::string& log) {
  const pid_t pid = ::fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) ::dup2(fd, STDOUT_FILENO), ::dup2(fd, STDERR_FILENO);
    if (::chdir(folder.c_str()) != 0) ::_exit(126);
    ::execlp(program.c_str(), program.c_str(), script.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

std::string gnuplot_program() {
  static const std::string program = [] {
    if (const char* p = std::getenv("EITBENCH_GNUPLOT"); p && *p) return std::string(p);
    const char* path = std::getenv("PATH");
    std::istringstream dirs(path ? path : "");
    for (std::string dir; std::getline(dirs, dir, ':');)
      if (!dir.empty() && ::access((fs::path(dir) / "gnuplot").c_str(), X_OK) == 0)
        return (fs::path(dir) / "gnuplot").string();
    return std::string();
  }();
  return program;
}

std::string series_colour(const std::string& key) {
  const auto& known = method_colours();
  if (const auto it = known.find(key); it != known.end()) return it->second;
  static const char* others[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b"};
  return others[std::hash<std::string>{}(key) % 6];
}

bool write_plot(const LinePlot& plot, const std::string& png_path) {
  const fs::path png(png_path);
  const fs::path folder = png.parent_path().empty() ? fs::path(".") : png.parent_path();
  const std::string name = png.stem().string();
  const std::string data = data_text(plot), script = script_text(plot, name, 900, 560);
  const std::string program = gnuplot_program();
  if (program.empty()) {
    write_bytes_atomically((folder / (name + ".dat")).string(), data);
    write_bytes_atomically((folder / (name + ".gp")).string(), script);
    return false;
  }
  // Drawn in a folder of its own beside the figure, then moved into place file by file: gnuplot
  // writes its outputs as it goes, and a failure leaves none of them.
  const fs::path work = folder / fmt::format(".{}.gnuplot{}", name, ::getpid());
  fs::remove_all(work);
  fs::create_directories(work);
  try {
    std::ofstream(work / (name + ".dat"), std::ios::binary) << data;
    std::ofstream(work / (name + ".gp"), std::ios::binary) << script;
    const int status = run_in(program, work.string(), name + ".gp", (work / "log").string());
    if (status != 0 || !fs::exists(work / (name + ".png")))
      throw InputError(png_path, "",
                       fmt::format("gnuplot ({}) failed drawing it (status {}): {}", program,
                                   status, file_text(work / "log")));
    for (const char* ext : {".dat", ".gp", ".svg", ".png"})
      fs::rename(work / (name + ext), folder / (name + ext));
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(work, ignored);
    throw;
  }
  fs::remove_all(work);
  return true;
}

}  // namespace eitbench
