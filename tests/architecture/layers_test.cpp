// The layers of src/ include one another only as docs/architecture.md's table allows: the table
// is read from the document itself (its "may include" column), and every `#include "folder/..."`
// in every source file is checked against it, so the document is the rule and the tree cannot
// drift from it; a dependency against the layering fails here first.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace dualcell {
namespace {

// The cells of a Markdown table row "| a | b | c |", trimmed.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row);
  std::string cell;
  std::getline(s, cell, '|');  // before the first bar
  while (std::getline(s, cell, '|')) {
    const std::size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    out.push_back(a == std::string::npos ? std::string() : cell.substr(a, b - a + 1));
  }
  if (!out.empty() && out.back().empty()) out.pop_back();  // after the last bar
  return out;
}

// docs/architecture.md's "## Layers" table: folder → the folders it may include. "—" and
// "nothing" allow none; "any of the above" (apps) is marked by the folder "*".
std::map<std::string, std::set<std::string>> layers_table() {
  std::ifstream in(testing::source_dir() + "/docs/architecture.md");
  EXPECT_TRUE(in) << "docs/architecture.md";
  std::map<std::string, std::set<std::string>> table;
  std::string line;
  bool in_layers = false;
  while (std::getline(in, line)) {
    if (line.rfind("## ", 0) == 0) in_layers = line == "## Layers";
    if (!in_layers || line.rfind("| `", 0) != 0) continue;
    const std::vector<std::string> row = cells(line);
    if (row.size() != 3) {
      ADD_FAILURE() << "a layers row without 3 cells: " << line;
      continue;
    }
    const std::string folder = row[0].substr(1, row[0].find('`', 1) - 1);
    std::set<std::string>& may = table[folder];
    if (row[2] == "any of the above") {
      may.insert("*");
      continue;
    }
    if (row[2] == "—" || row[2] == "nothing") continue;
    std::stringstream names(row[2]);
    std::string name;
    while (std::getline(names, name, ',')) {
      const std::size_t a = name.find_first_not_of(' '), b = name.find_last_not_of(' ');
      may.insert(name.substr(a, b - a + 1));
    }
  }
  return table;
}

TEST(Architecture, TheDocumentedTableIsComplete) {
  const auto table = layers_table();
  ASSERT_GE(table.size(), 15u) << "the table of docs/architecture.md was not found";
  for (const auto& entry : std::filesystem::directory_iterator(testing::source_dir() + "/src"))
    if (entry.is_directory()) {
      EXPECT_TRUE(table.count(entry.path().filename().string()))
          << "src/" << entry.path().filename().string() << " is not in docs/architecture.md's table";
    }
  for (const auto& [folder, may] : table) {
    EXPECT_TRUE(std::filesystem::is_directory(testing::source_dir() + "/src/" + folder))
        << "docs/architecture.md names src/" << folder << ", which does not exist";
    for (const std::string& other : may) {
      EXPECT_TRUE(other == "*" || table.count(other)) << folder << " may include " << other << ", not a layer";
    }
  }
}

TEST(Architecture, LayersIncludeOnlyWhatTheTableAllows) {
  const auto allowed = layers_table();
  const std::filesystem::path src = testing::source_dir() + "/src";
  // The folder of `#include "folder/file"`, or empty (GCC 12 warns inside std::regex under the
  // sanitizers, so this is parsed by hand).
  const auto included_folder = [](const std::string& line) -> std::string {
    const std::size_t hash = line.find_first_not_of(" \t");
    if (hash == std::string::npos || line.compare(hash, 8, "#include") != 0) return {};
    const std::size_t quote = line.find('"', hash);
    const std::size_t slash = quote == std::string::npos ? quote : line.find('/', quote);
    return slash == std::string::npos ? std::string() : line.substr(quote + 1, slash - quote - 1);
  };
  int checked = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(src)) {
    if (!entry.is_regular_file()) continue;
    const std::string layer = entry.path().parent_path().filename().string();
    const auto rule = allowed.find(layer);
    ASSERT_NE(rule, allowed.end()) << "folder src/" << layer << " is not in docs/architecture.md's table";
    if (rule->second.count("*")) continue;
    std::ifstream in(entry.path());
    std::string line;
    while (std::getline(in, line)) {
      const std::string target = included_folder(line);
      if (target.empty()) continue;
      ++checked;
      if (target == layer) continue;
      EXPECT_TRUE(rule->second.count(target)) << entry.path().string() << " includes " << target << "/: " << layer
                                              << " may include only what docs/architecture.md lists";
    }
  }
  EXPECT_GT(checked, 100);  // the scan saw the tree
}

// Whether MPI is built in is known to one source, src/par/parallel.cpp (the ranks layer's calls,
// each with its one-rank form): every other object of the build with MPI is the one of the build
// without it. The serial build's check rests on this (pipelines/Makefile, test-serial: its stages
// through the pipelines' tools and builds-agree; the unit tests run in the release build).
TEST(Architecture, OnlyTheRanksLayerKnowsWhetherMpiIsBuiltIn) {
  const std::string root = testing::source_dir();
  int scanned = 0;
  for (const char* tree : {"/src", "/tests"})
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root + tree)) {
      const std::string ext = entry.path().extension().string();
      if (!entry.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".c" && ext != ".h")) continue;
      if (entry.path() == std::filesystem::path(root + "/src/par/parallel.cpp")) continue;
      ++scanned;
      std::ifstream in(entry.path());
      std::string line;
      int number = 0;
      while (std::getline(in, line)) {
        ++number;
        // The two names spelled apart, so that this file does not name them.
        for (const std::string& name : {std::string("DUALCELL_") + "HAVE_MPI", std::string("<mpi") + ".h>"})
          EXPECT_EQ(line.find(name), std::string::npos)
              << entry.path().string() << ":" << number << " uses " << name << ": only src/par/parallel.cpp may";
      }
    }
  EXPECT_GT(scanned, 150);  // the scan saw both trees
}

}  // namespace
}  // namespace dualcell
