#pragma once
// splat-eval's charts, drawn by gnuplot (run as a subprocess on a generated script) as PNG
// (pngcairo) and SVG, from whichever result files the output folder holds:
//   results.json   psnr_vs_time, ssim_vs_time, psnr_vs_model_bytes, psnr_vs_gaussians,
//                  render_ms_vs_psnr: a series per method
//   sweep.json     sweep_psnr_vs_gaussians (and its points on the three charts above)
//   stability.json stability_psnr
#include <filesystem>
#include <string>
#include <vector>

namespace splat::cli {

// Writes out/charts/<chart>.{dat,png,svg} and out/charts/charts.gp (the script, kept so a
// chart can be restyled by hand); returns the chart images written, relative to out
// ("charts/psnr_vs_time.png", ...), or none with `gnuplot_missing` when gnuplot is not
// installed (the numbers stay in the JSON), or none when the files hold nothing to chart.
// InputError when `out` holds no result file: a report of nothing says what is missing
// where; Error when gnuplot runs and fails, naming its log.
struct ChartsDrawn {
  std::vector<std::string> images;
  bool gnuplot_missing = false;
};
ChartsDrawn write_charts(const std::filesystem::path& out);

}  // namespace splat::cli
