#pragma once
// Finds and loads the OpenImageIO plugin (oiio_plugin.hpp) the first time a file needs it.
#include <filesystem>

#include "splat/data/oiio_plugin.hpp"

namespace splat {

// The plugin's functions, loaded once per process from lib/splat/libsplat_oiio.so beside the
// running program's folder (build/bin → build/lib/splat; <prefix>/bin → <prefix>/lib/splat).
// Throws InputError naming `file` (the image that needed it) when the plugin is missing, will
// not load or is of another version.
const oiio_plugin::Api& oiio_plugin_for(const std::filesystem::path& file);

}  // namespace splat
