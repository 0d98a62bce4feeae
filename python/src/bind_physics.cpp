// Meshes, the forward model and its Jacobian (eitbench/jacobian).
#include <memory>

#include "bindings.h"
#include "eitbench/jacobian.h"

namespace eitbench::python {

void bind_physics(py::module_& m) {
  py::class_<Mesh, std::shared_ptr<Mesh>>(m, "Mesh", "A sensor's triangle mesh and its electrodes")
      .def_property_readonly(
          "nodes", [](const Mesh& mesh) { return mesh.nodes; }, "N x 2 node coordinates")
      .def_property_readonly(
          "triangles", [](const Mesh& mesh) { return mesh.triangles; },
          "T x 3 node indices, counter-clockwise")
      .def_property_readonly(
          "electrodes",
          [](const Mesh& mesh) {
            std::vector<std::vector<std::array<int, 2>>> out;
            for (const Electrode& e : mesh.electrodes) out.push_back(e.segments);
            return out;
          },
          "each electrode's boundary segments (node pairs), electrode 0 first")
      .def_property_readonly("num_triangles", &Mesh::num_triangles)
      .def_property_readonly("num_electrodes", &Mesh::num_electrodes)
      .def("__repr__", [](const Mesh& mesh) {
        return "<eitbench.Mesh: " + std::to_string(mesh.num_nodes()) + " nodes, " +
               std::to_string(mesh.num_triangles()) + " triangles, " +
               std::to_string(mesh.num_electrodes()) + " electrodes>";
      });

  m.def(
      "disk_mesh",
      [](int electrodes, const std::string& density, double radius, double coverage) {
        DiskMeshOptions o;
        o.electrodes = electrodes, o.density = parse_density(density);
        o.radius = radius, o.electrode_coverage = coverage;
        return std::make_shared<Mesh>(generate_disk_mesh(o));
      },
      py::arg("electrodes") = 16, py::arg("density") = "medium", py::arg("radius") = 1.0,
      py::arg("coverage") = 0.5,
      "The D_L-symmetric disk mesh (density coarse | medium | fine), as `eitbench mesh` makes it");
  m.def(
      "read_mesh",
      [](const std::string& path) { return std::make_shared<Mesh>(read_msh_file(path)); },
      py::arg("path"), "A Gmsh mesh (.msh 2.2 or 4.1, ASCII) with electrode_0.. groups");
  m.def(
      "conductivity_from_circles",
      [](const Mesh& mesh, const std::vector<std::array<double, 4>>& circles, double background) {
        std::vector<Circle> c;
        for (const auto& x : circles) c.push_back({x[0], x[1], x[2], x[3]});
        return conductivity_from_circles(mesh, c, background);
      },
      py::arg("mesh"), py::arg("circles"), py::arg("background") = 0.05,
      "Element conductivities of circles [x, y, r, sigma] on the background (exact overlaps)");

  py::class_<ForwardModel, std::shared_ptr<ForwardModel>>(
      m, "ForwardModel", "The complete electrode model on a mesh, adjacent drive and measurement")
      .def(py::init([](const Mesh& mesh, double contact_impedance, double current) {
             ForwardOptions o;
             o.contact_impedance = contact_impedance, o.current = current;
             return std::make_shared<ForwardModel>(mesh, o);
           }),
           py::arg("mesh"), py::arg("contact_impedance") = 0.01, py::arg("current") = 1.0)
      .def(
          "frame",
          [](const ForwardModel& f, const Eigen::Ref<const Eigen::VectorXd>& sigma,
             const std::string& order) {
            return f.frame(Eigen::VectorXd(sigma), parse_order(order));
          },
          py::arg("sigma"), py::arg("order") = "rotating",
          "The L(L-3) voltages for element conductivities sigma (rotating or ascending order)")
      .def(
          "difference",
          [](const ForwardModel& f, const Eigen::Ref<const Eigen::VectorXd>& sigma,
             double background) {
            const Eigen::VectorXd s = sigma;
            const Eigen::VectorXd empty = Eigen::VectorXd::Constant(s.size(), background);
            return f.protocol().reduce(f.frame(s) - f.frame(empty), MeasurementOrder::rotating);
          },
          py::arg("sigma"), py::arg("background") = 0.05,
          "The reduced difference frame v(sigma) - v(background): L(L-3)/2 values, the "
          "reconstructors' input")
      .def(
          "jacobian",
          [](const ForwardModel& f, const Eigen::Ref<const Eigen::VectorXd>& sigma) {
            return f.jacobian(f.solve(sigma), f.protocol().reduced_pairs());
          },
          py::arg("sigma"), "d v / d sigma on elements: reduced rows x triangles")
      .def_property_readonly("measurements",
                             [](const ForwardModel& f) { return f.protocol().frame_size(); });
}

}  // namespace eitbench::python
