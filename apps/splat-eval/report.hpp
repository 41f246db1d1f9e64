#pragma once
// report.html: one self-contained page (no scripts, no network) with splat-eval's tables,
// charts and comparison grids, from whichever result files the output folder holds
// (results.json, sweep.json, stability.json) and the charts drawn beside them.
#include <filesystem>

namespace splat::cli {

// Writes out/report.html through a temporary name and returns its path.
std::filesystem::path write_report(const std::filesystem::path& out);

}  // namespace splat::cli
