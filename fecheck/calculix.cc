#include "fecheck/calculix.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <utility>

#include "absl/container/flat_hash_map.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/strip.h"

namespace femsimp::fecheck {

int ModalDeck(const TetMesh& mesh, const Material& material, int eigenvalues, std::ostream& out) {
  std::vector<double> nodes = mesh.nodes;
  absl::flat_hash_map<uint64_t, uint32_t> midpoints;  // edge (low << 32 | high) -> node
  auto mid = [&](uint32_t a, uint32_t b) {
    const uint64_t key = uint64_t{std::min(a, b)} << 32 | std::max(a, b);
    auto [it, added] = midpoints.emplace(key, static_cast<uint32_t>(nodes.size() / 3));
    if (added)
      for (int k = 0; k < 3; ++k) nodes.push_back((nodes[3 * a + k] + nodes[3 * b + k]) / 2);
    return it->second;
  };
  // C3D10: corners 1-4, then the edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4.
  std::vector<uint32_t> elements;
  elements.reserve(10 * mesh.num_tets());
  for (size_t t = 0; t < mesh.num_tets(); ++t) {
    const uint32_t* v = &mesh.tets[4 * t];
    elements.insert(elements.end(), v, v + 4);
    for (const auto& [a, b] : {std::pair{0, 1}, {1, 2}, {2, 0}, {0, 3}, {1, 3}, {2, 3}})
      elements.push_back(mid(v[a], v[b]));
  }
  // %.14g: CalculiX reads a number from the first 20 characters of its field. Ids are 1-based.
  out << "*HEADING\nfemsimp FE check: free-free modal analysis\n*NODE\n";
  for (size_t n = 0; n < nodes.size() / 3; ++n)
    out << absl::StrFormat("%u, %.14g, %.14g, %.14g\n", n + 1, nodes[3 * n], nodes[3 * n + 1],
                           nodes[3 * n + 2]);
  out << "*ELEMENT, TYPE=C3D10, ELSET=EALL\n";
  for (size_t t = 0; t < mesh.num_tets(); ++t) {
    out << t + 1;
    for (int i = 0; i < 10; ++i) out << (i == 8 ? ",\n" : ", ") << elements[10 * t + i] + 1;
    out << '\n';
  }
  out << absl::StrFormat("*MATERIAL, NAME=M\n*ELASTIC\n%.14g, %.14g\n*DENSITY\n%.14g\n",
                         material.youngs_modulus, material.poisson_ratio, material.density)
      << "*SOLID SECTION, ELSET=EALL, MATERIAL=M\n*STEP\n*FREQUENCY\n"
      << eigenvalues << "\n*END STEP\n";
  return static_cast<int>(nodes.size() / 3);
}

absl::StatusOr<std::vector<double>> ParseEigenvalues(const std::string& dat) {
  const size_t table = dat.find("E I G E N V A L U E   O U T P U T");
  if (table == std::string::npos)
    return absl::InvalidArgumentError("no eigenvalue table (E I G E N V A L U E   O U T P U T)");
  std::istringstream in(dat.substr(table));
  std::vector<double> eigenvalues;
  std::string line;
  std::getline(in, line);  // the title
  while (std::getline(in, line)) {
    // A row: mode number, eigenvalue, then the frequencies; the headings and blank lines before
    // the rows are skipped, and the next heading ends the table.
    std::istringstream row(line);
    int mode = 0;
    double eigenvalue = 0;
    if (!(row >> mode >> eigenvalue)) {
      if (!eigenvalues.empty() && !absl::StripAsciiWhitespace(line).empty()) break;
      continue;
    }
    if (mode != static_cast<int>(eigenvalues.size()) + 1) break;
    eigenvalues.push_back(eigenvalue);
  }
  if (eigenvalues.empty()) return absl::InvalidArgumentError("the eigenvalue table is empty");
  return eigenvalues;
}

Modes SplitRigidModes(const std::vector<double>& eigenvalues, int elastic_wanted) {
  std::vector<double> hz;
  for (double e : eigenvalues) hz.push_back(e > 0 ? std::sqrt(e) / (2 * std::numbers::pi) : 0.0);
  std::sort(hz.begin(), hz.end());
  const double highest = hz.empty() ? 0.0 : hz.back();
  Modes modes;
  for (double f : hz) {
    if (f <= kRigidFraction * highest) {
      ++modes.rigid;
    } else if (static_cast<int>(modes.elastic_hz.size()) < elastic_wanted) {
      modes.elastic_hz.push_back(f);
    }
  }
  return modes;
}

absl::StatusOr<Modes> FreeFreeModes(const TetMesh& mesh, const Material& material,
                                    int elastic_wanted, const ToolRun& run) {
  const int wanted = 6 * std::max(1, mesh.components) + elastic_wanted;
  int quadratic_nodes = 0;
  {
    std::ofstream deck(run.dir + "/modal.inp");
    quadratic_nodes = ModalDeck(mesh, material, wanted, deck);
    if (!deck.flush())
      return absl::InternalError(absl::StrCat("cannot write ", run.dir, "/modal.inp"));
  }
  absl::StatusOr<ToolExit> ran = RunTool(kCalculix, {"modal"}, run);
  if (!ran.ok()) return ran.status();
  // ccx may report an input error with exit code 0: its "*ERROR" lines count as failure too.
  std::ifstream log_in(ran->log_path);
  const std::string log((std::istreambuf_iterator<char>(log_in)), {});
  if (!ran->exit.ok() || absl::StrContains(log, "*ERROR"))
    return absl::InternalError(ToolFailure(kCalculix, *ran));
  std::ifstream dat_in(run.dir + "/modal.dat");
  const std::string dat((std::istreambuf_iterator<char>(dat_in)), {});
  absl::StatusOr<std::vector<double>> eigenvalues = ParseEigenvalues(dat);
  if (!eigenvalues.ok())
    return absl::InternalError(
        ToolFailure(kCalculix, *ran, absl::StrCat("modal.dat: ", eigenvalues.status().message())));
  Modes modes = SplitRigidModes(*eigenvalues, elastic_wanted);
  modes.nodes = quadratic_nodes;
  return modes;
}

}  // namespace femsimp::fecheck
