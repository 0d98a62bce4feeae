#include "eitbench/bench/report/loss_curves.h"

#include <iomanip>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/figures.h"
#include "eitbench/bench/report/gnuplot.h"

namespace eitbench {

bool write_loss_curves(
    const std::string& csv_path, const std::string& png_path,
    const std::vector<std::pair<std::string, std::vector<TrainingRecord>>>& runs) {
  write_text_atomically(csv_path, [&](std::ostream& out) {
    out << "run,round,epoch,steps,samples,train_loss,validation_loss,learning_rate,seconds,"
           "samples_per_second\n";
    out << std::setprecision(9);
    for (const auto& [name, history] : runs)
      for (const auto& r : history)
        out << name << ',' << r.round << ',' << r.epoch << ',' << r.steps << ',' << r.samples << ','
            << r.train_loss << ',' << r.validation_loss << ',' << r.learning_rate << ','
            << r.seconds << ',' << r.samples_per_second << '\n';
  });
  LinePlot plot;
  plot.title = "MSE against samples seen: training (dashed) and validation";
  plot.x_label = "training samples seen";
  plot.y_label = "MSE (per pixel)";
  plot.log_y = true;
  for (const auto& [name, history] : runs) {
    PlotSeries train, validation;
    for (const auto& r : history) {
      train.x.push_back(double(r.samples)), train.y.push_back(r.train_loss);
      validation.x.push_back(double(r.samples)), validation.y.push_back(r.validation_loss);
    }
    const std::string prefix = runs.size() > 1 ? name + " " : "";
    validation.label = prefix + "validation";
    train.label = prefix + "training";
    validation.key = train.key = "dnn (" + name + ")";
    train.dashed = true;
    plot.series.push_back(train);
    plot.series.push_back(validation);
  }
  return write_plot(plot, png_path);
}

}  // namespace eitbench
