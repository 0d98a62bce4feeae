// The stage cache's form of a method's results.
#include "stages.h"

namespace eitbench::run {

nlohmann::json to_json(const MethodResults& r) {
  nlohmann::json rows = nlohmann::json::array(), images = nlohmann::json::array();
  for (const auto& row : r.rows) rows.push_back(to_json(row));
  for (const auto& im : r.images)
    images.push_back(std::vector<float>(im.data(), im.data() + im.size()));
  return {{"rows", rows}, {"images", images}};
}

MethodResults method_results_from(const nlohmann::json& j) {
  MethodResults r;
  for (const auto& row : j.at("rows")) {
    // A stage finished before the touch metrics lacks them: at() throws, and the stage runs again.
    (void)row.at("touch");
    r.rows.push_back(result_row_from_json(row));
  }
  for (const auto& im : j.at("images")) {
    const auto v = im.get<std::vector<float>>();
    r.images.push_back(
        Eigen::Map<const Eigen::VectorXf>(v.data(), static_cast<Eigen::Index>(v.size()))
            .cast<double>());
  }
  return r;
}

}  // namespace eitbench::run
