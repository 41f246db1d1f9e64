#include "splat/data/view_names.hpp"

#include <map>

#include "splat/core/error.hpp"

namespace splat {

namespace fs = std::filesystem;

std::vector<std::string> view_names(const std::vector<fs::path>& image_paths, const fs::path& file) {
  std::map<std::string, int> stems;
  for (const fs::path& path : image_paths) ++stems[path.stem().string()];
  std::vector<std::string> names;
  std::map<std::string, std::size_t> first_with;
  for (std::size_t i = 0; i < image_paths.size(); ++i) {
    const fs::path path = image_paths[i].lexically_normal();
    std::string name = path.stem().string();
    if (stems[name] > 1) {
      name = (path.parent_path() / path.stem()).generic_string();
      for (char& c : name)
        if (c == '/') c = '_';
    }
    if (const auto [it, added] = first_with.emplace(name, i); !added)
      throw InputError(file, "views " + std::to_string(it->second) + " and " + std::to_string(i) + " (" +
                                 image_paths[it->second].generic_string() + ", " + image_paths[i].generic_string() +
                                 ") would both be named '" + name + "': a view's name names its outputs");
    names.push_back(std::move(name));
  }
  return names;
}

}  // namespace splat
