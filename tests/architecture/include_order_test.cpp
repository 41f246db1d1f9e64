// The include rules of docs/DESIGN.md §2, checked on the sources: the library's modules only
// include lower layers (the order is read from DESIGN's ```layers block, the same block the
// build reads), a program includes the library, apps/common and its own folder, and every
// quoted include is rooted at the repository. The build already refuses most upward includes
// (each module sees only the include roots of the layers below); this test names them all at
// once, file and line, and also covers what the build cannot see (a header no one compiles
// yet, a program including another's files, a bare header name that happens to resolve).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace splat {
namespace {

namespace fs = std::filesystem;

const fs::path kSourceRoot = SPLAT_SOURCE_DIR;

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Module → layer index (0 = lowest), from the ```layers block of docs/DESIGN.md.
std::map<std::string, int> read_layers() {
  const std::string design = read_text(kSourceRoot / "docs" / "DESIGN.md");
  const std::string open = "```layers\n";
  const std::size_t start = design.find(open);
  if (start == std::string::npos) return {};
  const std::size_t end = design.find("```", start + open.size());
  std::istringstream block(design.substr(start + open.size(), end - start - open.size()));
  std::map<std::string, int> layer_of;
  std::string line;
  for (int layer = 0; std::getline(block, line);) {
    std::istringstream modules(line);
    std::string module;
    bool any = false;
    while (modules >> module) {
      layer_of[module] = layer;
      any = true;
    }
    if (any) ++layer;
  }
  return layer_of;
}

struct Include {
  fs::path file;  // relative to the repository
  int line = 0;
  std::string path;  // as written between the quotes
};

// Every #include "..." of the C++ files under `folder` (relative to the repository).
std::vector<Include> quoted_includes(const fs::path& folder) {
  static const std::regex kInclude(R"re(^\s*#\s*include\s+"([^"]+)")re");
  std::vector<Include> includes;
  if (!fs::is_directory(kSourceRoot / folder)) return includes;
  for (const auto& entry : fs::recursive_directory_iterator(kSourceRoot / folder)) {
    const std::string extension = entry.path().extension().string();
    if (!entry.is_regular_file() || (extension != ".cpp" && extension != ".hpp" && extension != ".h")) continue;
    std::ifstream in(entry.path());
    std::string line;
    std::smatch match;
    for (int number = 1; std::getline(in, line); ++number)
      if (std::regex_search(line, match, kInclude))
        includes.push_back({fs::relative(entry.path(), kSourceRoot), number, match[1]});
  }
  return includes;
}

// The first component of `path` after `prefix`/ ("splat/raster/x.hpp", "splat" → "raster");
// empty when `path` does not start with it.
std::string component_after(const std::string& path, const std::string& prefix) {
  if (path.rfind(prefix + "/", 0) != 0) return {};
  const std::string rest = path.substr(prefix.size() + 1);
  const std::size_t slash = rest.find('/');
  return slash == std::string::npos ? std::string() : rest.substr(0, slash);
}

std::string where(const Include& include) {
  return include.file.generic_string() + ":" + std::to_string(include.line) + ": \"" + include.path + "\"";
}

// The violations of the rules among `includes` (one line each), given the layer order.
std::vector<std::string> violations(const std::vector<Include>& includes, const std::map<std::string, int>& layer_of) {
  std::vector<std::string> found;
  for (const Include& include : includes) {
    const std::string file = include.file.generic_string();
    if (!fs::is_regular_file(kSourceRoot / include.path)) {
      found.push_back(where(include) + " is not a path from the repository root");
      continue;
    }
    if (const std::string module = component_after(file, "splat"); !module.empty()) {
      const std::string target = component_after(include.path, "splat");
      if (target.empty()) {
        found.push_back(where(include) + ": the library includes only the library");
      } else if (!layer_of.count(module) || !layer_of.count(target)) {
        found.push_back(where(include) + ": module not in the layers of docs/DESIGN.md §2");
      } else if (target != module && layer_of.at(target) >= layer_of.at(module)) {
        found.push_back(where(include) + ": " + module + " (layer " + std::to_string(layer_of.at(module)) +
                        ") may not include " + target + " (layer " + std::to_string(layer_of.at(target)) + ")");
      }
    } else if (const std::string program = component_after(file, "apps"); !program.empty()) {
      const std::string target_program = component_after(include.path, "apps");
      const bool library = include.path.rfind("splat/", 0) == 0;
      if (!library && target_program != "common" && target_program != program)
        found.push_back(where(include) + ": a program includes the library, apps/common and its own folder");
    }
  }
  return found;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += "  " + line + "\n";
  return text;
}

TEST(IncludeOrder, DesignNamesEveryModuleOnceAndNoTopLevelFolderSharesAModulesName) {
  const std::map<std::string, int> layer_of = read_layers();
  ASSERT_FALSE(layer_of.empty()) << "docs/DESIGN.md has no ```layers block";
  std::set<std::string> folders;
  for (const auto& entry : fs::directory_iterator(kSourceRoot / "splat"))
    if (entry.is_directory()) folders.insert(entry.path().filename().string());
  for (const std::string& folder : folders)
    EXPECT_TRUE(layer_of.count(folder)) << "splat/" << folder << " is not in the layers of docs/DESIGN.md §2";
  for (const auto& [module, layer] : layer_of) {
    EXPECT_TRUE(folders.count(module)) << "docs/DESIGN.md §2 names a module splat/" << module << " that is not there";
    EXPECT_FALSE(fs::exists(kSourceRoot / module)) << "top-level folder " << module << "/ shares its name with splat/"
                                                   << module;
  }
}

TEST(IncludeOrder, EveryIncludeFollowsTheLayersAndIsRootedAtTheRepository) {
  const std::map<std::string, int> layer_of = read_layers();
  ASSERT_FALSE(layer_of.empty());
  std::vector<Include> includes;
  for (const char* folder : {"splat", "apps", "tests", "bench", "fuzz"}) {
    const std::vector<Include> more = quoted_includes(folder);
    includes.insert(includes.end(), more.begin(), more.end());
  }
  ASSERT_GT(includes.size(), 500u);  // the tree was read
  const std::vector<std::string> found = violations(includes, layer_of);
  EXPECT_TRUE(found.empty()) << found.size() << " include(s) against docs/DESIGN.md §2:\n" << joined(found);
}

// The checker itself: an upward include, a same-layer include, a bare name and a program
// reaching into another's folder are each caught; a downward include is not.
TEST(IncludeOrder, TheCheckCatchesEachKindOfViolation) {
  const std::map<std::string, int> layer_of = read_layers();
  ASSERT_TRUE(layer_of.count("core") && layer_of.count("raster") && layer_of.count("nerf") &&
              layer_of.count("gaussians"));
  const std::vector<Include> bad = {
      {"splat/core/camera.hpp", 1, "splat/raster/rasterizer.hpp"},            // up
      {"splat/nerf/rays_user.hpp", 2, "splat/gaussians/gaussian_model.hpp"},  // same layer
      {"splat/raster/project.cpp", 3, "project.hpp"},                         // not rooted
      {"apps/splat-eval/x.cpp", 4, "apps/splat-train/train_command.hpp"},     // another program
  };
  EXPECT_EQ(violations(bad, layer_of).size(), bad.size()) << joined(violations(bad, layer_of));
  const std::vector<Include> good = {
      {"splat/raster/project.cpp", 1, "splat/core/camera.hpp"},
      {"splat/raster/project.cpp", 2, "splat/raster/project.hpp"},
      {"apps/splat-eval/x.cpp", 3, "apps/common/arg_parser.hpp"},
      {"tests/raster/x_test.cpp", 4, "tests/test_support.hpp"},
  };
  EXPECT_TRUE(violations(good, layer_of).empty()) << joined(violations(good, layer_of));
}

}  // namespace
}  // namespace splat
