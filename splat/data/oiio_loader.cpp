#include "splat/data/oiio_loader.hpp"

#include <dlfcn.h>

#include <string>
#include <system_error>

#include "splat/core/error.hpp"

namespace splat {
namespace {

constexpr const char* kPluginPath = "../lib/splat/libsplat_oiio.so";  // from the program's folder

// The plugin, or why it could not be had (the error wording's end).
struct Loaded {
  const oiio_plugin::Api* api = nullptr;
  std::string problem;
};

Loaded load_plugin() {
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {nullptr, "cannot find the running program (/proc/self/exe): " + ec.message()};
  const std::filesystem::path plugin = (program.parent_path() / kPluginPath).lexically_normal();
  // RTLD_LOCAL: OpenImageIO's symbols stay out of the program's scope.
  void* handle = dlopen(plugin.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) return {nullptr, "cannot load " + plugin.string() + ": " + dlerror()};
  using Entry = const oiio_plugin::Api* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, "splat_oiio_plugin_api"));
  if (!entry) return {nullptr, plugin.string() + " is not the splat OpenImageIO plugin"};
  const oiio_plugin::Api* api = entry();
  if (!api || api->version != oiio_plugin::kApiVersion)
    return {nullptr, plugin.string() + " is of another version than the program (rebuild both)"};
  return {api, {}};  // never unloaded: OpenImageIO keeps threads and caches until exit
}

}  // namespace

const oiio_plugin::Api& oiio_plugin_for(const std::filesystem::path& file) {
  static const Loaded loaded = load_plugin();  // once, thread-safe
  if (!loaded.api) throw InputError(file, "this format needs OpenImageIO, whose plugin is unavailable: " + loaded.problem);
  return *loaded.api;
}

}  // namespace splat
