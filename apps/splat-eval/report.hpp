#pragma once
// report.html: one self-contained page (no scripts, no network) with splat-eval's tables,
// charts and comparison grids, from whichever result files the output folder holds
// (results.json, sweep.json, stability.json) and the charts drawn beside them.
#include <filesystem>
#include <string>

namespace splat::cli {

// The report page of the result files in `out` (InputError naming a damaged one); the charts
// it shows are those drawn by then.
std::string report_html(const std::filesystem::path& out);
// Writes out/report.html through a temporary name and returns its path.
std::filesystem::path write_report(const std::filesystem::path& out);

}  // namespace splat::cli
