// Gmsh ASCII .msh 2.2 and 4.1. The reader checks every count against the bytes that remain before
// it allocates, so a corrupt header cannot ask for gigabytes, and names the section and line of
// anything it cannot use.
#include "eitbench/jacobian/msh_io.h"

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

#include "eitbench/jacobian/error.h"
#include "eitbench/jacobian/input_file.h"
#include "eitbench/jacobian/read_budget.h"

namespace eitbench {
namespace {

class Tokens {
 public:
  Tokens(std::string text, std::string source)
      : text_(std::move(text)), source_(std::move(source)) {}

  bool done() {
    skip_space();
    return pos_ >= text_.size();
  }
  std::string word(const std::string& field) {
    skip_space();
    if (pos_ >= text_.size()) fail(field, "the file ends early");
    if (text_[pos_] == '"') {
      const std::size_t end = text_.find('"', pos_ + 1);
      if (end == std::string::npos) fail(field, "unterminated quoted name");
      std::string out = text_.substr(pos_ + 1, end - pos_ - 1);
      pos_ = end + 1;
      return out;
    }
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  long long integer(const std::string& field,
                    long long lo = std::numeric_limits<long long>::min()) {
    const std::string w = word(field);
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(w.c_str(), &end, 10);
    if (w.empty() || *end != '\0' || errno == ERANGE) fail(field, "'" + w + "' is not an integer");
    if (v < lo) fail(field, "value " + w + " is out of range");
    return v;
  }
  double real(const std::string& field) {
    const std::string w = word(field);
    errno = 0;
    char* end = nullptr;
    const double v = std::strtod(w.c_str(), &end);
    if (w.empty() || *end != '\0' || errno == ERANGE) fail(field, "'" + w + "' is not a number");
    if (!std::isfinite(v)) fail(field, "value is NaN or infinite");
    return v;
  }
  void expect(const std::string& word_expected) {
    const std::string w = word(word_expected);
    if (w != word_expected)
      fail(word_expected, "expected '" + word_expected + "', found '" + w + "'");
  }
  // A count of items that each take at least `bytes_each` bytes of the rest of the file.
  std::size_t count(const std::string& field, std::size_t bytes_each) {
    const long long n = integer(field, 0);
    if (static_cast<unsigned long long>(n) > (text_.size() - pos_) / bytes_each + 1)
      fail(field, "declares " + std::to_string(n) + " items, more than the file can hold");
    return static_cast<std::size_t>(n);
  }
  void skip_section(const std::string& name) {
    const std::string end = "$End" + name.substr(1);
    while (!done())
      if (word(end) == end) return;
    fail(name, "section has no " + end);
  }
  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw InputError(source_, field + " (line " + std::to_string(line()) + ")", message);
  }
  const std::string& source() const { return source_; }

 private:
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  int line() const {
    return 1 + static_cast<int>(std::count(text_.begin(), text_.begin() + pos_, '\n'));
  }
  std::string text_;
  std::string source_;
  std::size_t pos_ = 0;
};

// Gmsh lets an entity belong to many physical groups; a mesh uses a handful. More is a hostile
// file (50,000 tags on one entity, copied to each of its 50,000 elements, asked for gigabytes).
constexpr std::size_t kMaxPhysicalTags = 64;

struct RawElement {
  int dim;
  int physical;  // index into RawMesh::physical_lists: an entity's list is shared, not copied
  std::array<long long, 3> nodes;
};

struct RawMesh {
  std::map<std::pair<int, int>, std::string> names;  // (dim, physical tag) -> name
  std::map<long long, std::array<double, 2>> nodes;
  std::vector<std::vector<int>> physical_lists{{}};  // list 0: no physical group
  std::vector<RawElement> elements;
};

// Gmsh element types eitbench can use: 15 point, 1 two-node line, 2 three-node triangle.
int nodes_of_type(long long type, Tokens& in, const std::string& field) {
  switch (type) {
    case 15:
      return 1;
    case 1:
      return 2;
    case 2:
      return 3;
    default:
      in.fail(field, "element type " + std::to_string(type) +
                         " is not supported (linear triangles, lines and points only)");
  }
}
int dim_of_type(long long type) {
  return type == 15 ? 0 : type == 1 ? 1 : 2;
}

void read_physical_names(Tokens& in, RawMesh& raw) {
  const std::size_t n = in.count("$PhysicalNames", 6);
  for (std::size_t i = 0; i < n; ++i) {
    const int dim = static_cast<int>(in.integer("$PhysicalNames dimension", 0));
    const int tag = static_cast<int>(in.integer("$PhysicalNames tag"));
    raw.names[{dim, tag}] = in.word("$PhysicalNames name");
  }
  in.expect("$EndPhysicalNames");
}

void add_node(Tokens& in, RawMesh& raw, long long tag, double x, double y) {
  if (!raw.nodes.emplace(tag, std::array<double, 2>{x, y}).second)
    in.fail("$Nodes", "node " + std::to_string(tag) + " is defined twice");
}

void read_v2(Tokens& in, RawMesh& raw) {
  std::map<long long, int> list_of;  // physical tag -> its one-tag list
  while (!in.done()) {
    const std::string section = in.word("section");
    if (section == "$PhysicalNames") {
      read_physical_names(in, raw);
    } else if (section == "$Nodes") {
      const std::size_t n = in.count("$Nodes count", 8);
      for (std::size_t i = 0; i < n; ++i) {
        const long long tag = in.integer("$Nodes tag");
        const double x = in.real("$Nodes x"), y = in.real("$Nodes y");
        in.real("$Nodes z");
        add_node(in, raw, tag, x, y);
      }
      in.expect("$EndNodes");
    } else if (section == "$Elements") {
      const std::size_t n = in.count("$Elements count", 10);
      for (std::size_t i = 0; i < n; ++i) {
        in.integer("$Elements tag");
        const long long type = in.integer("$Elements type");
        const std::size_t tags = in.count("$Elements number of tags", 2);
        long long physical = 0;  // the first tag; the others (entity, partitions) are not used
        for (std::size_t k = 0; k < tags; ++k) {
          const long long tag = in.integer("$Elements tags");
          if (k == 0) physical = tag;
        }
        const int count = nodes_of_type(type, in, "$Elements");
        RawElement e{dim_of_type(type), 0, {}};
        if (physical != 0) {
          const auto [it, added] =
              list_of.emplace(physical, static_cast<int>(raw.physical_lists.size()));
          if (added) raw.physical_lists.push_back({static_cast<int>(physical)});
          e.physical = it->second;
        }
        for (int k = 0; k < count; ++k) e.nodes[k] = in.integer("$Elements node");
        raw.elements.push_back(e);
      }
      in.expect("$EndElements");
    } else if (!section.empty() && section[0] == '$') {
      in.skip_section(section);
    } else {
      in.fail("section", "unexpected '" + section + "' outside any section");
    }
  }
}

void read_v4(Tokens& in, RawMesh& raw) {
  std::map<std::pair<int, int>, int> entity_physical;  // (dim, entity) -> physical list
  while (!in.done()) {
    const std::string section = in.word("section");
    if (section == "$PhysicalNames") {
      read_physical_names(in, raw);
    } else if (section == "$Entities") {
      std::size_t counts[4];
      for (auto& c : counts) c = in.count("$Entities count", 8);
      for (int dim = 0; dim < 4; ++dim)
        for (std::size_t i = 0; i < counts[dim]; ++i) {
          const int tag = static_cast<int>(in.integer("$Entities tag"));
          for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) in.real("$Entities bounding box");
          const std::size_t np = in.count("$Entities physical count", 2);
          if (np > kMaxPhysicalTags)
            in.fail("$Entities physical count",
                    "entity " + std::to_string(tag) + " belongs to " + std::to_string(np) +
                        " physical groups, more than the " + std::to_string(kMaxPhysicalTags) +
                        " a mesh can use");
          std::vector<int> phys;
          for (std::size_t k = 0; k < np; ++k)
            phys.push_back(static_cast<int>(in.integer("$Entities physical tag")));
          entity_physical[{dim, tag}] = static_cast<int>(raw.physical_lists.size());
          raw.physical_lists.push_back(std::move(phys));
          if (dim > 0) {
            const std::size_t nb = in.count("$Entities bounding count", 2);
            for (std::size_t k = 0; k < nb; ++k) in.integer("$Entities bounding tag");
          }
        }
      in.expect("$EndEntities");
    } else if (section == "$Nodes") {
      const std::size_t blocks = in.count("$Nodes blocks", 8);
      in.count("$Nodes count", 8);
      in.integer("$Nodes min tag");
      in.integer("$Nodes max tag");
      for (std::size_t b = 0; b < blocks; ++b) {
        const int dim = static_cast<int>(in.integer("$Nodes entity dimension", 0));
        in.integer("$Nodes entity tag");
        const long long parametric = in.integer("$Nodes parametric", 0);
        const std::size_t n = in.count("$Nodes block size", 8);
        std::vector<long long> tags(n);
        for (auto& t : tags) t = in.integer("$Nodes tag");
        for (std::size_t i = 0; i < n; ++i) {
          const double x = in.real("$Nodes x"), y = in.real("$Nodes y");
          in.real("$Nodes z");
          if (parametric)
            for (int k = 0; k < std::min(dim, 2); ++k) in.real("$Nodes parametric coordinate");
          add_node(in, raw, tags[i], x, y);
        }
      }
      in.expect("$EndNodes");
    } else if (section == "$Elements") {
      const std::size_t blocks = in.count("$Elements blocks", 8);
      in.count("$Elements count", 4);
      in.integer("$Elements min tag");
      in.integer("$Elements max tag");
      for (std::size_t b = 0; b < blocks; ++b) {
        const int dim = static_cast<int>(in.integer("$Elements entity dimension", 0));
        const int entity = static_cast<int>(in.integer("$Elements entity tag"));
        const long long type = in.integer("$Elements type");
        const std::size_t n = in.count("$Elements block size", 4);
        const int count = nodes_of_type(type, in, "$Elements");
        if (dim_of_type(type) != dim)
          in.fail("$Elements", "element type does not match its entity's dimension");
        const auto it = entity_physical.find({dim, entity});
        for (std::size_t i = 0; i < n; ++i) {
          in.integer("$Elements tag");
          RawElement e{dim, it == entity_physical.end() ? 0 : it->second, {}};
          for (int k = 0; k < count; ++k) e.nodes[k] = in.integer("$Elements node");
          raw.elements.push_back(e);
        }
      }
      in.expect("$EndElements");
    } else if (!section.empty() && section[0] == '$') {
      in.skip_section(section);
    } else {
      in.fail("section", "unexpected '" + section + "' outside any section");
    }
  }
}

// Electrode index from a physical name "electrode_<k>", or -1.
int electrode_index(const std::string& name) {
  const std::string prefix = "electrode_";
  if (name.rfind(prefix, 0) != 0 || name.size() == prefix.size() || name.size() > prefix.size() + 6)
    return -1;
  for (std::size_t i = prefix.size(); i < name.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(name[i]))) return -1;
  return std::stoi(name.substr(prefix.size()));
}

Mesh assemble(const RawMesh& raw, Tokens& in) {
  const std::string& source = in.source();
  if (raw.nodes.empty()) throw InputError(source, "$Nodes", "the file has no nodes");
  std::map<long long, int> index;
  Mesh mesh;
  mesh.nodes.resize(static_cast<Eigen::Index>(raw.nodes.size()), 2);
  for (const auto& [tag, xy] : raw.nodes) {
    const int i = static_cast<int>(index.size());
    index[tag] = i;
    mesh.nodes.row(i) << xy[0], xy[1];
  }
  auto node = [&](long long tag) {
    const auto it = index.find(tag);
    if (it == index.end())
      throw InputError(source, "$Elements",
                       "refers to node " + std::to_string(tag) + ", which $Nodes does not define");
    return it->second;
  };

  std::map<std::pair<int, int>, int> electrode_of;  // (dim, physical) -> electrode
  std::set<int> domain;                             // 2-D physical tags
  int max_electrode = -1;
  for (const auto& [key, name] : raw.names) {
    const int e = electrode_index(name);
    if (e >= 0 && (key.first == 0 || key.first == 1)) {
      for (const auto& [other, f] : electrode_of)
        if (f == e) throw InputError(source, name, "is defined by more than one physical group");
      electrode_of[key] = e;
      max_electrode = std::max(max_electrode, e);
    }
  }
  for (const auto& [key, name] : raw.names)
    if (key.first == 2) domain.insert(key.second);
  if (max_electrode < 0)
    throw InputError(source, "$PhysicalNames",
                     "no physical group named electrode_0, electrode_1, ...");
  for (int e = 0; e <= max_electrode; ++e) {
    bool found = false;
    for (const auto& [key, f] : electrode_of) found |= (f == e);
    if (!found)
      throw InputError(source, "electrode_" + std::to_string(e),
                       "is missing: electrodes must be numbered 0 .. L-1 without gaps");
  }

  mesh.electrodes.resize(max_electrode + 1);
  std::vector<std::vector<int>> points(max_electrode + 1);
  std::vector<std::array<int, 3>> triangles;
  for (const RawElement& el : raw.elements) {
    if (el.dim == 2) {
      bool in_domain = domain.empty();
      for (int p : raw.physical_lists[el.physical]) in_domain |= domain.count(p) > 0;
      if (in_domain) triangles.push_back({node(el.nodes[0]), node(el.nodes[1]), node(el.nodes[2])});
      continue;
    }
    for (int p : raw.physical_lists[el.physical]) {
      const auto it = electrode_of.find({el.dim, p});
      if (it == electrode_of.end()) continue;
      if (el.dim == 1)
        mesh.electrodes[it->second].segments.push_back({node(el.nodes[0]), node(el.nodes[1])});
      else
        points[it->second].push_back(node(el.nodes[0]));
    }
  }
  for (int e = 0; e <= max_electrode; ++e) {
    auto& el = mesh.electrodes[e];
    const std::string field = "electrode_" + std::to_string(e);
    if (!points[e].empty() && !el.segments.empty())
      throw InputError(source, field, "mixes points and line segments");
    if (points[e].size() > 1)
      throw InputError(
          source, field,
          "a point electrode must be a single node, found " + std::to_string(points[e].size()));
    if (points[e].size() == 1) el.point_node = points[e][0];
    if (el.is_point() && el.point_node < 0) throw InputError(source, field, "has no elements");
  }
  if (triangles.empty())
    throw InputError(source, "$Elements", "the file has no triangles in its 2-D physical groups");
  mesh.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    mesh.triangles.row(t) << triangles[t][0], triangles[t][1], triangles[t][2];
  normalize_mesh(mesh);
  validate_mesh(mesh, source);
  return mesh;
}

}  // namespace

Mesh read_msh(std::istream& stream, const std::string& source) {
  std::stringstream buffer;
  buffer << stream.rdbuf();
  Tokens in(buffer.str(), source);
  if (in.done()) throw InputError(source, "$MeshFormat", "the file is empty");
  in.expect("$MeshFormat");
  const std::string version = in.word("$MeshFormat version");
  const long long file_type = in.integer("$MeshFormat file-type");
  in.integer("$MeshFormat data-size");
  if (file_type != 0)
    in.fail("$MeshFormat", "binary .msh files are not supported: save the mesh as ASCII");
  // A binary file would carry its endianness marker here; ASCII goes straight to the end tag.
  in.expect("$EndMeshFormat");
  RawMesh raw;
  if (version == "2.2" || version == "2.1" || version == "2")
    read_v2(in, raw);
  else if (version == "4.1")
    read_v4(in, raw);
  else
    in.fail("$MeshFormat", "version " + version + " is not supported (2.2 or 4.1)");
  return assemble(raw, in);
}

Mesh read_msh_file(const std::string& path) {
  require_input_file(path);
  // The reader holds the text twice and a node or element per few bytes of it: rule 2 of
  // read_budget.h, with the file itself counted against the cap.
  std::error_code error;
  const double size = static_cast<double>(std::filesystem::file_size(path, error));
  ReadBudget(path).take("", 2 * size, "a text of " + byte_size_text(size));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "", "cannot open the file");
  return read_msh(in, path);
}

void write_msh(std::ostream& out, const Mesh& mesh, MshVersion version) {
  const int L = mesh.num_electrodes(), N = mesh.num_nodes(), T = mesh.num_triangles();
  const int domain_tag = L + 1;  // electrode e is physical tag e + 1
  out << std::setprecision(17);
  out << "$MeshFormat\n"
      << (version == MshVersion::v22 ? "2.2" : "4.1") << " 0 8\n$EndMeshFormat\n";
  out << "$PhysicalNames\n" << L + 1 << "\n";
  for (int e = 0; e < L; ++e)
    out << (mesh.electrodes[e].is_point() ? 0 : 1) << " " << e + 1 << " \"electrode_" << e
        << "\"\n";
  out << "2 " << domain_tag << " \"domain\"\n$EndPhysicalNames\n";
  std::size_t line_count = 0;
  for (const auto& e : mesh.electrodes) line_count += e.is_point() ? 1 : e.segments.size();

  if (version == MshVersion::v22) {
    out << "$Nodes\n" << N << "\n";
    for (int i = 0; i < N; ++i)
      out << i + 1 << " " << mesh.nodes(i, 0) << " " << mesh.nodes(i, 1) << " 0\n";
    out << "$EndNodes\n$Elements\n" << line_count + T << "\n";
    std::size_t id = 1;
    for (int e = 0; e < L; ++e) {
      const auto& el = mesh.electrodes[e];
      if (el.is_point())
        out << id++ << " 15 2 " << e + 1 << " " << e + 1 << " " << el.point_node + 1 << "\n";
      for (const auto& s : el.segments)
        out << id++ << " 1 2 " << e + 1 << " " << e + 1 << " " << s[0] + 1 << " " << s[1] + 1
            << "\n";
    }
    for (int t = 0; t < T; ++t)
      out << id++ << " 2 2 " << domain_tag << " 1 " << mesh.triangles(t, 0) + 1 << " "
          << mesh.triangles(t, 1) + 1 << " " << mesh.triangles(t, 2) + 1 << "\n";
    out << "$EndElements\n";
    return;
  }

  // 4.1: one entity per electrode (a point or a curve, tag e + 1) and one surface (tag 1).
  const Eigen::Vector2d lo = mesh.nodes.colwise().minCoeff(), hi = mesh.nodes.colwise().maxCoeff();
  int point_entities = 0;
  for (const auto& e : mesh.electrodes) point_entities += e.is_point();
  out << "$Entities\n" << point_entities << " " << L - point_entities << " 1 0\n";
  for (int e = 0; e < L; ++e)
    if (mesh.electrodes[e].is_point()) {
      const int n = mesh.electrodes[e].point_node;
      out << e + 1 << " " << mesh.nodes(n, 0) << " " << mesh.nodes(n, 1) << " 0 1 " << e + 1
          << "\n";
    }
  for (int e = 0; e < L; ++e) {
    const auto& el = mesh.electrodes[e];
    if (el.is_point()) continue;
    Eigen::Vector2d a = mesh.nodes.row(el.segments[0][0]), b = a;
    for (const auto& s : el.segments)
      for (int k : s)
        a = a.cwiseMin(Eigen::Vector2d(mesh.nodes.row(k))),
        b = b.cwiseMax(Eigen::Vector2d(mesh.nodes.row(k)));
    out << e + 1 << " " << a.x() << " " << a.y() << " 0 " << b.x() << " " << b.y() << " 0 1 "
        << e + 1 << " 0\n";
  }
  out << "1 " << lo.x() << " " << lo.y() << " 0 " << hi.x() << " " << hi.y() << " 0 1 "
      << domain_tag << " 0\n";
  out << "$EndEntities\n";
  out << "$Nodes\n1 " << N << " 1 " << N << "\n2 1 0 " << N << "\n";
  for (int i = 0; i < N; ++i) out << i + 1 << "\n";
  for (int i = 0; i < N; ++i) out << mesh.nodes(i, 0) << " " << mesh.nodes(i, 1) << " 0\n";
  out << "$EndNodes\n";
  const std::size_t total = line_count + T;
  out << "$Elements\n" << L + 1 << " " << total << " 1 " << total << "\n";
  std::size_t id = 1;
  for (int e = 0; e < L; ++e) {
    const auto& el = mesh.electrodes[e];
    if (el.is_point()) {
      out << "0 " << e + 1 << " 15 1\n" << id++ << " " << el.point_node + 1 << "\n";
      continue;
    }
    out << "1 " << e + 1 << " 1 " << el.segments.size() << "\n";
    for (const auto& s : el.segments) out << id++ << " " << s[0] + 1 << " " << s[1] + 1 << "\n";
  }
  out << "2 1 2 " << T << "\n";
  for (int t = 0; t < T; ++t)
    out << id++ << " " << mesh.triangles(t, 0) + 1 << " " << mesh.triangles(t, 1) + 1 << " "
        << mesh.triangles(t, 2) + 1 << "\n";
  out << "$EndElements\n";
}

}  // namespace eitbench
