#include "eitbench/bench/methods/registry.h"

#include "eitbench/jacobian/error.h"
#include "method_specs.h"

namespace eitbench {

const std::vector<MethodSpec>& method_registry() {
  // clang-format off
  static const std::vector<MethodSpec> registry{
      methods::tikhonov(), methods::noser(), methods::laplace(), methods::smooth(),
      methods::total_variation(), methods::gauss_newton(), methods::greit(),
#ifdef EITBENCH_HAVE_CERES  // a build without Ceres has no shape fit
      methods::shape(), methods::shape_linear(),
#endif
      methods::learned()};
  // clang-format on
  return registry;
}

const std::vector<std::string>& method_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const auto& m : method_registry()) out.push_back(m.name);
    return out;
  }();
  return names;
}

std::vector<std::string> model_based_method_names() {
  std::vector<std::string> out;
  for (const auto& m : method_registry())
    if (m.make) out.push_back(m.name);
  return out;
}

std::vector<std::string> method_names_with(bool MethodSpec::*property) {
  std::vector<std::string> out;
  for (const auto& m : method_registry())
    if (m.*property) out.push_back(m.name);
  return out;
}

std::string joined_method_names_with(bool MethodSpec::*property) {
  std::string out;
  for (const auto& name : method_names_with(property)) out += (out.empty() ? "" : ", ") + name;
  return out;
}

const MethodSpec& find_method(const std::string& name) {
  for (const auto& m : method_registry())
    if (m.name == name) return m;
  throw InputError("--method", "", "unknown method '" + name + "'");
}

std::unique_ptr<Reconstructor> make_reconstructor(const std::string& name,
                                                  std::shared_ptr<const LinearProblem> problem,
                                                  const MethodOptions& options) {
  const MethodSpec& spec = find_method(name);
  if (!spec.make)
    throw InputError("--model", "",
                     "the " + name + " method needs a trained model (eitbench train)");
  MethodOptions resolved = options;  // an empty choice is the method's default
  if (resolved.choose.empty()) resolved.choose = spec.default_choice;
  return spec.make(std::move(problem), resolved);
}

}  // namespace eitbench
