// The structure the folders promise (docs/architecture.md), checked on the sources: every header
// includes only its own layer and the layers below it; the umbrella header includes every core
// header except the opt-in and optional ones; OpenMP is spoken in platform/team.hpp alone; the 3x3
// block product is written once (linalg/block3.hpp); installed headers cite models and papers, not
// a course brief; the docs, headers, benchmarks and scripts describe the software, not a development
// diary; every deliberate bug of the mutation list still finds its text.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const fs::path source_dir = DRAPE_SOURCE_DIR;

/// The layers of include/drape, each with the layers it may include (itself and those below it).
const std::map<std::string, std::set<std::string>> allowed = {
    {"platform", {"platform"}},
    {"core", {"platform", "core"}},
    {"linalg", {"platform", "core", "linalg"}},
    {"collision", {"platform", "core", "collision"}},
    {"contact", {"platform", "core", "linalg", "collision", "contact"}},
    {"model", {"platform", "core", "linalg", "collision", "contact", "model"}},
    {"physics", {"platform", "core", "linalg", "collision", "contact", "model", "physics"}},
    {"solvers", {"platform", "core", "linalg", "solvers"}},
    {"integrators",
     {"platform", "core", "linalg", "collision", "contact", "model", "physics", "solvers", "integrators"}},
    {"scene",
     {"platform", "core", "linalg", "collision", "contact", "model", "physics", "solvers", "integrators", "scene"}},
    {"realtime", {"platform", "core", "realtime"}},
    {"io", {"platform", "core", "io"}},
    {"garment", {"platform", "core", "linalg", "collision", "contact", "model", "physics", "garment"}},
};
/// Headers at the top of include/drape that any layer may include.
const std::set<std::string> shared_top = {"config.hpp", "fwd.hpp"};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<fs::path> headers(const fs::path& root) {
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.path().extension() == ".hpp") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

/// The drape headers `text` includes, as paths below include/ ("drape/platform/team.hpp").
std::vector<std::string> drape_includes(const std::string& text) {
  static const std::regex include(R"re(#include\s+["<](drape/[^">]+)[">])re");
  std::vector<std::string> out;
  for (std::sregex_iterator it(text.begin(), text.end(), include), end; it != end; ++it) out.push_back((*it)[1]);
  return out;
}

}  // namespace

TEST_CASE("every header includes only its layer and the layers below it", "[layers]") {
  const fs::path root = source_dir / "include" / "drape";
  int checked = 0;
  for (const fs::path& header : headers(root)) {
    const fs::path relative = fs::relative(header, root);
    if (relative.parent_path().empty()) continue;  // drape.hpp, fwd.hpp, config.hpp
    const std::string layer = relative.begin()->string();
    INFO(relative.string());
    REQUIRE(allowed.count(layer) == 1);  // a new folder must be placed in the table above
    for (const std::string& included : drape_includes(read(header))) {
      const fs::path target = fs::path(included).lexically_relative("drape");
      INFO("includes " << included);
      if (target.parent_path().empty()) {
        CHECK(shared_top.count(target.string()) == 1);
        continue;
      }
      CHECK(allowed.at(layer).count(target.begin()->string()) == 1);
      ++checked;
    }
  }
  CHECK(checked > 50);
}

TEST_CASE("the umbrella header includes every core header but the opt-in and optional ones", "[layers]") {
  const fs::path root = source_dir / "include" / "drape";
  const std::vector<std::string> included = drape_includes(read(root / "drape.hpp"));
  const std::set<std::string> in_umbrella(included.begin(), included.end());
  // Compile-time opt-ins (the compiled instances, Eigen's direct solvers: solver_registry.hpp says
  // why) and the SuiteSparse back ends.
  const std::set<std::string> left_out = {"drape/solvers/enable_ldlt.hpp",  "drape/solvers/enable_lu.hpp",
                                          "drape/solvers/eigen_direct.hpp", "drape/solvers/cholmod.hpp",
                                          "drape/solvers/umfpack.hpp",      "drape/instances.hpp",
                                          "drape/drape.hpp"};
  // A header of a detail folder is a part of its layer's headers: one of them includes it instead.
  std::set<std::string> included_in_layer;  // "layer drape/..."
  for (const fs::path& header : headers(root)) {
    const std::string layer = fs::relative(header, root).begin()->string();
    for (const std::string& name : drape_includes(read(header))) included_in_layer.insert(layer + " " + name);
  }
  for (const fs::path& header : headers(root)) {
    const fs::path relative = fs::relative(header, root);
    const std::string name = "drape/" + relative.generic_string();
    INFO(name);
    if (header.parent_path().filename() == "detail") {
      CHECK(included_in_layer.count(relative.begin()->string() + " " + name) == 1);
      CHECK(in_umbrella.count(name) == 0);
      continue;
    }
    // The garment layer is included on its own (drape/garment/garment_mesh.hpp): the pattern, its
    // curves and the panel mesher are not compiled into every user of the umbrella.
    if (relative.begin()->string() == "garment") {
      CHECK(in_umbrella.count(name) == 0);
      continue;
    }
    CHECK(in_umbrella.count(name) + left_out.count(name) == 1);
  }
}

TEST_CASE("OpenMP appears in platform/team.hpp only; the 3x3 block product in linalg/block3.hpp only", "[layers]") {
  // Three unrolled products m[0] x0 + m[3] x1 + m[6] x2 on one line are the block product.
  const std::regex unrolled(R"(\w\[0\] \* [^;]*\w\[3\] \* [^;]*\w\[6\] \* )");
  for (const fs::path& dir : {source_dir / "include", source_dir / "viewer"}) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      const std::string ext = e.path().extension().string();
      if (ext != ".hpp" && ext != ".cpp") continue;
      const std::string text = read(e.path());
      const std::string name = e.path().filename().string();
      INFO(e.path().string());
      if (e.path() != source_dir / "include" / "drape" / "platform" / "team.hpp") {
        CHECK(text.find("#pragma omp") == std::string::npos);
        CHECK(text.find("_OPENMP") == std::string::npos);
        CHECK(text.find("omp_get") == std::string::npos);
      }
      if (name != "block3.hpp") CHECK_FALSE(std::regex_search(text, unrolled));
    }
  }
}

TEST_CASE("installed headers do not speak of the course brief", "[layers][docs]") {
  for (const fs::path& dir : {source_dir / "include", source_dir / "viewer" / "include"})
    for (const fs::path& header : headers(dir)) {
      INFO(header.string());
      CHECK(read(header).find("brief") == std::string::npos);
    }
}

TEST_CASE("docs, README, headers, benchmarks and scripts describe the software, not a development diary",
          "[layers][docs]") {
  // A reader needs what the software does and what was measured on which machine, not when or in
  // which work session it was done: no numbered sessions or issues, no "guest" for the machine, no
  // course brief. A Dask, client or pytest session is a thing the software has, and allowed.
  const auto icase = std::regex::ECMAScript | std::regex::icase;
  const std::regex diary(R"(\bsessions?\b|\bissues?\s+#?[0-9]+|\bguests?\b|\b(the|course)\s+brief\b)", icase);
  const std::regex allowed(R"(\b(dask|client|pytest)\s+sessions?\b)", icase);
  const std::vector<std::string> keys = {"session", "issue", "guest", "brief"};
  const std::set<std::string> text_files = {".md", ".hpp", ".cpp", ".h", ".py", ".sh", ".txt", ".cmake", ".toml"};
  std::vector<fs::path> files = {source_dir / "README.md"};
  for (const char* dir : {"docs", "include", "bench", "scripts"})
    for (const auto& e : fs::recursive_directory_iterator(source_dir / dir))
      if (e.is_regular_file() && text_files.count(e.path().extension().string()) == 1) files.push_back(e.path());
  std::sort(files.begin(), files.end());

  const auto lower = [](std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
  };
  int lines = 0;
  for (const fs::path& file : files) {
    const std::string name = fs::relative(file, source_dir).generic_string();
    std::istringstream text(read(file));
    int number = 0;
    for (std::string line; std::getline(text, line);) {
      ++number;
      ++lines;
      const std::string folded = lower(line);
      const auto has = [&](const std::string& key) { return folded.find(key) != std::string::npos; };
      if (std::none_of(keys.begin(), keys.end(), has)) continue;  // std::regex is slow: match candidates only
      if (!std::regex_search(std::regex_replace(line, allowed, ""), diary)) continue;
      FAIL_CHECK(name << ":" << number << ": " << line);
    }
  }
  CHECK(files.size() > 100);
  CHECK(lines > 15000);
}

TEST_CASE("every deliberate bug of tests/mutations.tsv names text that is in its file", "[layers][mutations]") {
  // scripts/mutation_check.sh stops at a row whose text has moved; this finds it in every CTest
  // run, not only when someone runs the check.
  std::ifstream list(source_dir / "tests" / "mutations.tsv");
  REQUIRE(list);
  int rows = 0;
  for (std::string line; std::getline(list, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> field;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, '\t');) field.push_back(f);
    INFO(line);
    REQUIRE(field.size() == 5);
    CHECK(read(source_dir / field[1]).find(field[2]) != std::string::npos);
    ++rows;
  }
  CHECK(rows > 100);
}
