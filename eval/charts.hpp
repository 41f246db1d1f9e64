#pragma once
// splat-eval's charts: test PSNR and SSIM over training time for both methods, drawn by
// gnuplot (run as a subprocess on a generated script) as PNG (pngcairo) and SVG.
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace splat::cli {

// Writes dir/history.dat (the curves' numbers), dir/charts.gp (the script, kept so a chart
// can be restyled by hand) and dir/{psnr,ssim}_vs_time.{png,svg}; returns the chart files
// written, relative to dir. `methods` is results.json's "methods" array. Returns an empty list
// when gnuplot is not installed (the numbers stay in results.json); throws Error when gnuplot
// runs and fails, naming its log.
std::vector<std::string> write_charts(const nlohmann::json& methods, const std::filesystem::path& dir);

}  // namespace splat::cli
