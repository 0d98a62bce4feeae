#include "eitbench/bench/report/loss_curves.h"

#include <array>
#include <iomanip>

#include "eitbench/bench/io/atomic_file.h"
#include "eitbench/bench/report/figures.h"

namespace eitbench {

void write_loss_curves(
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
  static const std::array<int, 3> colours[] = {{200, 90, 20},  {40, 160, 40},  {30, 30, 200},
                                               {160, 40, 160}, {20, 160, 200}, {90, 90, 90}};
  LinePlot plot;
  plot.title = "MSE against samples seen: training (light) and validation";
  plot.x_label = "training samples seen";
  plot.y_label = "MSE";
  plot.log_y = true;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const auto& [name, history] = runs[k];
    const auto colour = colours[k % 6];
    PlotSeries train, validation;
    for (const auto& r : history) {
      train.x.push_back(double(r.samples)), train.y.push_back(r.train_loss);
      validation.x.push_back(double(r.samples)), validation.y.push_back(r.validation_loss);
    }
    const std::string prefix = runs.size() > 1 ? name + " " : "";
    validation.label = prefix + "validation";
    validation.colour = colour;
    train.label = prefix + "training";
    train.colour = {(colour[0] + 255 * 2) / 3, (colour[1] + 255 * 2) / 3,
                    (colour[2] + 255 * 2) / 3};
    plot.series.push_back(train);
    plot.series.push_back(validation);
  }
  if (can_draw_figures()) draw_plot_png(plot, png_path);
}

}  // namespace eitbench
