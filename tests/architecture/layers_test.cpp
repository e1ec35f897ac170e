// The layers of src/ include one another only as docs/architecture.md's table allows: every
// `#include "folder/..."` in every source file is checked against it, so the document and the
// tree cannot drift apart, and a dependency against the layering fails here first.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>

#include "test_util.hpp"

namespace dualcell {
namespace {

// The table of docs/architecture.md ("may include"); apps may include every layer.
const std::map<std::string, std::set<std::string>> allowed = {
    {"core", {}},
    {"linalg", {}},
    {"qp", {}},
    {"mesh", {"core"}},
    {"fem", {"core", "mesh"}},
    {"feti", {"core", "mesh", "fem", "linalg", "qp", "law", "par"}},
    {"sweep", {"core", "feti"}},
    {"law", {"core"}},
    {"structure", {"core", "fem", "linalg", "law"}},
    {"io", {"core", "mesh", "fem", "feti", "sweep", "law", "structure"}},
    {"fit", {"core", "sweep", "law", "io"}},
    {"par", {"core"}},
    {"stage", {"core", "mesh", "feti", "sweep", "law", "io", "fit", "structure", "par"}},
    {"study", {"core", "mesh", "fem", "linalg", "feti", "io", "par"}},
    {"umat", {}},  // C for other FE codes: includes nothing of the project
};

TEST(Architecture, LayersIncludeOnlyWhatTheTableAllows) {
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
    if (layer == "apps") continue;
    const auto rule = allowed.find(layer);
    ASSERT_NE(rule, allowed.end()) << "folder src/" << layer << " is not in docs/architecture.md's table";
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

}  // namespace
}  // namespace dualcell
