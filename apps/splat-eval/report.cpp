#include "apps/splat-eval/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "splat/core/atomic_file.hpp"
#include "apps/splat-eval/result_files.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fixed(double value, int decimals) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", decimals, value);
  return text;
}

// "600" or "0.5": seconds with a decimal only where it matters.
std::string seconds(const json& value) {
  const double s = value.get<double>();
  return fixed(s, s < 10 ? 1 : 0);
}

std::string megabytes(const json& bytes) { return fixed(bytes.get<double>() / 1e6, 2); }

std::string model_size(const json& m) {
  return m.contains("num_gaussians") ? std::to_string(m.at("num_gaussians").get<long>()) + " Gaussians"
                                     : std::to_string(m.at("num_params").get<long>()) + " parameters";
}

// A chart as its PNG (what every browser shows), linked to the SVG when there is one.
void chart(std::ostream& html, const fs::path& out, const std::string& name) {
  const std::string png = "charts/" + name + ".png", svg = "charts/" + name + ".svg";
  if (!fs::exists(out / png)) return;
  html << "<figure><a href=\"" << svg << "\"><img src=\"" << png << "\" alt=\"" << name
       << "\" width=\"900\"></a></figure>\n";
}

// The first training time (s) at which `m`'s history scores at least `psnr`, if it does.
std::optional<double> seconds_to_psnr(const json& m, double psnr) {
  for (const json& h : m.value("history", json::array()))
    if (h.contains("test_psnr") && h.at("test_psnr").get<double>() >= psnr) return h.at("seconds").get<double>();
  return std::nullopt;
}

// Who wins where: the best score, the smallest file, the fastest render, and the first to
// the best quality every method reaches (the level all curves share, so the race is fair).
void comparison_verdicts(std::ostream& html, const json& methods) {
  if (methods.size() < 2) return;
  const auto best = [&](const auto& value, bool highest) {
    const json* winner = &methods.front();
    for (const json& m : methods)
      if (highest ? value(m) > value(*winner) : value(m) < value(*winner)) winner = &m;
    return winner;
  };
  const json* quality = best([](const json& m) { return m.at("final").at("psnr").get<double>(); }, true);
  const json* size = best([](const json& m) { return m.at("model_bytes").get<double>(); }, false);
  const json* render = best([](const json& m) { return m.at("render_ms_per_view_median").get<double>(); }, false);
  html << "<p>Who wins where:</p>\n<ul>\n<li>best test PSNR: <b>" << escaped(method_label(*quality)) << "</b> ("
       << fixed(quality->at("final").at("psnr"), 2) << " dB)</li>\n<li>smallest model file: <b>"
       << escaped(method_label(*size)) << "</b> (" << megabytes(size->at("model_bytes")) << " MB)</li>\n"
       << "<li>fastest render: <b>" << escaped(method_label(*render)) << "</b> ("
       << fixed(render->at("render_ms_per_view_median"), 1) << " ms per view)</li>\n";
  // The best score every method's curve reaches, and who reached it first.
  double shared = std::numeric_limits<double>::infinity();
  for (const json& m : methods) {
    double top = -std::numeric_limits<double>::infinity();
    for (const json& h : m.value("history", json::array()))
      if (h.contains("test_psnr")) top = std::max(top, h.at("test_psnr").get<double>());
    shared = std::min(shared, top);
  }
  if (std::isfinite(shared)) {
    const json* first = nullptr;
    double first_seconds = 0;
    for (const json& m : methods)
      if (const auto t = seconds_to_psnr(m, shared); t && (!first || *t < first_seconds)) first = &m, first_seconds = *t;
    if (first)
      html << "<li>first to " << fixed(shared, 2) << " dB (the best score every method reached during training): <b>"
           << escaped(method_label(*first)) << "</b>, after " << fixed(first_seconds, 1) << " s</li>\n";
  }
  html << "</ul>\n";
}

void comparison_section(std::ostream& html, const fs::path& out, const json& r) {
  html << "<h2>The methods under one budget</h2>\n<p>Dataset <code>" << escaped(r.at("data"))
       << "</code>: " << r.at("test_views") << " test views at " << r.at("width") << "&times;" << r.at("height")
       << "; each method trained for " << seconds(r.at("budget_seconds")) << " s of wall-clock time on "
       << r.at("threads") << " threads, scored every " << fixed(r.at("eval_every_seconds"), 1)
       << " s of training (scoring not counted).</p>\n";
  html << "<table><tr><th>method</th><th>test PSNR (dB)</th><th>SSIM</th><th>iterations</th>"
          "<th>training (s)</th><th>model</th><th>model file (MB)</th><th>render per view (ms, median)</th>"
          "<th>stopped by</th></tr>\n";
  for (const json& m : r.at("methods")) {
    html << "<tr><td>" << escaped(method_label(m)) << "</td><td>" << fixed(m.at("final").at("psnr"), 2) << "</td><td>"
         << fixed(m.at("final").at("ssim"), 4) << "</td><td>" << m.at("iterations") << "</td><td>"
         << fixed(m.at("train_seconds"), 1) << "</td><td>" << model_size(m) << "</td><td>"
         << megabytes(m.at("model_bytes")) << "</td><td>" << fixed(m.at("render_ms_per_view_median"), 1) << "</td><td>"
         << escaped(m.at("stopped_by")) << "</td></tr>\n";
  }
  html << "</table>\n";
  comparison_verdicts(html, r.at("methods"));
  // The methods flying one path (--fly-through), side by side.
  std::string videos;
  for (const json& m : r.at("methods"))
    if (m.contains("fly_through"))
      videos += "<figure><video src=\"" + escaped(m.at("fly_through").get<std::string>()) +
                "\" controls loop muted width=\"400\"></video><figcaption>" + escaped(method_label(m)) +
                "</figcaption></figure>\n";
  if (!videos.empty()) html << "<h3>Fly-throughs</h3>\n<div class=\"videos\">\n" << videos << "</div>\n";
  for (const char* name : {"psnr_vs_time", "ssim_vs_time", "psnr_vs_model_bytes", "psnr_vs_gaussians", "render_ms_vs_psnr"})
    chart(html, out, name);
  std::string panels;
  for (const json& panel : r.at("grid").at("panels")) panels += (panels.empty() ? "" : " | ") + panel.get<std::string>();
  html << "<h3>Test views</h3>\n<p>Each row: " << escaped(panels) << "; " << escaped(r.at("grid").at("error_map"))
       << ".</p>\n";
  // The grids results.json names; a folder from before it named them: what grids/ holds.
  std::vector<std::string> grids;
  for (const json& grid : r.value("grids", json::array())) grids.push_back(grid);
  if (grids.empty() && fs::is_directory(out / "grids")) {
    for (const auto& entry : fs::directory_iterator(out / "grids"))
      if (entry.path().extension() == ".png") grids.push_back("grids/" + entry.path().filename().string());
    std::sort(grids.begin(), grids.end());
  }
  for (const std::string& file : grids) {
    html << "<figure><img src=\"" << escaped(file) << "\" alt=\"" << escaped(file)
         << "\" class=\"grid\"><figcaption>" << escaped(fs::path(file).stem().string())
         << "</figcaption></figure>\n";
  }
}

void sweep_section(std::ostream& html, const fs::path& out, const json& s) {
  const long smallest = s.contains("smallest_within") ? s.at("smallest_within").get<long>() : -1;
  html << "<h2>Model no larger than the scene needs: Gaussian budgets</h2>\n<p>" << escaped(method_label(s)) << " trained "
       << seconds(s.at("budget_seconds")) << " s under each budget (<code>--max-gaussians</code>). Best test PSNR "
       << fixed(s.at("best_psnr"), 2) << " dB; <strong>marked</strong>: the smallest model within "
       << s.at("within_db") << " dB of it.</p>\n";
  html << "<table><tr><th>budget</th><th>Gaussians</th><th>model file (MB)</th><th>test PSNR (dB)</th>"
          "<th>SSIM</th><th>iterations</th><th>render per view (ms)</th></tr>\n";
  const json& runs = s.at("runs");
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const json& r = runs.at(i);
    html << (long(i) == smallest ? "<tr class=\"mark\">" : "<tr>") << "<td>" << r.at("max_gaussians") << "</td>";
    if (!r.contains("final")) {
      html << "<td colspan=\"6\">diverged at iteration " << r.at("diverged").at("iteration") << "</td></tr>\n";
      continue;
    }
    html << "<td>" << r.at("num_gaussians") << "</td><td>" << megabytes(r.at("model_bytes")) << "</td><td>"
         << fixed(r.at("final").at("psnr"), 2) << (long(i) == smallest ? " &#9664; smallest within" : "") << "</td><td>"
         << fixed(r.at("final").at("ssim"), 4) << "</td><td>" << r.at("iterations") << "</td><td>"
         << fixed(r.at("render_ms_per_view_median"), 1) << "</td></tr>\n";
  }
  html << "</table>\n";
  chart(html, out, "sweep_psnr_vs_gaussians");
}

// What refinement recovered: the refined runs' training cameras against the true poses.
void pose_error_table(std::ostream& html, const json& s) {
  std::ostringstream rows;
  const auto cell = [](const json& e) {
    return "<td>" + fixed(e.at("mean_rotation_deg"), 3) + "&deg; / " + fixed(e.at("mean_translation_percent_of_extent"), 3) +
           " %</td>";
  };
  for (const json& c : s.at("conditions"))
    for (const json& r : c.value("runs", json::array()))
      if (r.contains("pose_refinement") && r.at("pose_refinement").contains("pose_error")) {
        const json& e = r.at("pose_refinement").at("pose_error");
        rows << "<tr><td>" << escaped(c.at("name")) << "</td><td>" << escaped(method_label(r)) << "</td>"
             << cell(e.at("before")) << cell(e.at("after")) << "</tr>\n";
      }
  if (rows.str().empty()) return;
  html << "<p>The training cameras' pose error: the mean over the views of the turn and of the centre's offset "
          "(in % of the scene extent) from the true pose, after fitting a similarity to the centres (the frame a "
          "reconstruction lives in is free):</p>\n<table><tr><th>condition</th><th>method</th>"
          "<th>before training</th><th>after refinement</th></tr>\n"
       << rows.str() << "</table>\n";
}

// On a real capture, the baseline row asks whether training holds its best: per method, the
// best test point, the final score, the distance between them, and the curve.
void real_capture_table(std::ostream& html, const fs::path& out, const json& s) {
  if (!s.value("real_capture", false)) return;
  const auto baseline = std::find_if(s.at("conditions").begin(), s.at("conditions").end(),
                                     [](const json& c) { return c.at("kind") == "baseline"; });
  if (baseline == s.at("conditions").end() || !baseline->contains("runs")) return;
  html << "<h3>Real capture: does training hold its best?</h3>\n<p>The photographs with their structure-from-motion "
          "poses, all training views: each method's best test point, its final score, and whether it holds its best"
       << (s.at("rules").contains("holds_best") ? " (" + escaped(s.at("rules").at("holds_best")) + ")" : std::string())
       << ".</p>\n<table><tr><th>method</th><th>best PSNR (dB)</th><th>at (s)</th><th>final PSNR (dB)</th>"
          "<th>below its best (dB)</th><th>holds its best</th></tr>\n";
  for (const json& r : baseline->at("runs")) {
    html << "<tr><td>" << escaped(method_label(r)) << "</td>";
    if (!r.contains("best") || !r.contains("final")) {
      html << "<td colspan=\"5\">" << escaped(r.at("verdict")) << "</td></tr>\n";
      continue;
    }
    const bool holds = r.value("holds_best", false);
    html << "<td>" << fixed(r.at("best").at("psnr"), 2) << "</td><td>" << seconds(r.at("best").at("seconds"))
         << "</td><td>" << fixed(r.at("final").at("psnr"), 2) << "</td><td>" << fixed(r.at("drop_from_best"), 2)
         << "</td><td class=\"" << (holds ? "ok" : "degraded") << "\">" << (holds ? "yes" : "no") << "</td></tr>\n";
  }
  html << "</table>\n";
  chart(html, out, "stability_real_capture");
}

void stability_section(std::ostream& html, const fs::path& out, const json& s) {
  html << "<h2>Stability: where the methods fail</h2>\n<p>Dataset <code>" << escaped(s.at("data")) << "</code> ("
       << s.at("train_views") << " training views); every run trained " << seconds(s.at("budget_seconds"))
       << " s and was scored on the unchanged test views. Verdicts:</p>\n<ul>\n";
  for (const char* verdict : {"diverged", "collapsed", "failed", "degraded", "ok"})
    if (s.at("rules").contains(verdict))  // "failed" is newer than some result files
      html << "<li><b>" << verdict << "</b>: " << escaped(s.at("rules").at(verdict)) << "</li>\n";
  // The columns: every method that ran, in the order they first appear (the refinement rows
  // run only the splat methods).
  std::vector<std::string> methods;
  std::string protocol;  // how refined runs were scored
  for (const json& c : s.at("conditions"))
    for (const json& r : c.value("runs", json::array())) {
      if (std::find(methods.begin(), methods.end(), method_label(r)) == methods.end())
        methods.push_back(method_label(r));
      if (r.contains("pose_refinement")) protocol = r.at("pose_refinement").value("test_protocol", "");
    }
  html << "</ul>\n<table><tr><th>condition</th><th>training views</th>";
  for (const std::string& m : methods)
    html << "<th>" << escaped(m) << " PSNR (dB)</th><th>" << escaped(m) << " below its best (dB)</th><th>"
         << escaped(m) << " verdict</th><th>" << escaped(m) << " model (MB)</th>";
  html << "</tr>\n";
  for (const json& c : s.at("conditions")) {
    html << "<tr><td>" << escaped(c.at("name")) << "</td>";
    if (c.contains("skipped")) {
      html << "<td colspan=\"" << 1 + 4 * methods.size() << "\">not run: " << escaped(c.at("skipped")) << "</td></tr>\n";
      continue;
    }
    html << "<td>" << c.at("train_views") << "</td>";
    for (const std::string& m : methods) {
      const auto run = std::find_if(c.at("runs").begin(), c.at("runs").end(),
                                    [&](const json& r) { return method_label(r) == m; });
      if (run == c.at("runs").end()) {
        html << "<td colspan=\"4\">not run</td>";
        continue;
      }
      const json& r = *run;
      const std::string verdict = r.at("verdict");
      const std::string shown = r.contains("diverged")
                                    ? "diverged at iteration " + r.at("diverged").at("iteration").dump()
                                    : verdict;
      html << "<td>" << (r.contains("final") ? fixed(r.at("final").at("psnr"), 2) : "&ndash;") << "</td><td>"
           << (r.contains("drop_from_best") ? fixed(r.at("drop_from_best"), 2) : "&ndash;") << "</td><td class=\""
           << verdict << "\">" << escaped(shown) << "</td><td>"
           << (r.contains("model_bytes") ? megabytes(r.at("model_bytes")) : "&ndash;") << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table>\n";
  if (!protocol.empty())
    html << "<p>Rows marked &ldquo;+ refinement&rdquo; trained with <code>--refine-poses</code>: " << escaped(protocol)
         << ". The pose noise rows are trained on the perturbed poses; every row is scored against the same test "
            "views.</p>\n";
  real_capture_table(html, out, s);
  pose_error_table(html, s);
  chart(html, out, "stability_psnr");
  html << "<p>&ldquo;Below its best&rdquo; is the final test PSNR's distance from the best test point of the same "
          "run: a model that learns late what explains its training views and spoils the others (floaters on real "
          "captures) ends below its best. The curves of every run:</p>\n";
  chart(html, out, "stability_curves");
}

}  // namespace

std::string report_html(const fs::path& out) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>splat-eval report</title>\n"
          "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
          "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:4px 8px;"
          "text-align:right}th{background:#eee}td:first-child{text-align:left}tr.mark{background:#fff3b0}"
          ".degraded{background:#ffe0b0}.diverged,.collapsed,.failed{background:#ffc0c0}.ok{background:#d8f5d0}"
          "img.grid{width:100%;image-rendering:pixelated}figure{margin:1em 0}"
          "div.videos{display:flex;gap:1em}div.videos figure{margin:0}</style></head><body>\n"
          "<h1>splat-eval report</h1>\n";
  bool any = false;
  with_result_file(out / "results.json", [&](const json& results) { comparison_section(html, out, results), any = true; });
  with_result_file(out / "sweep.json", [&](const json& sweep) { sweep_section(html, out, sweep), any = true; });
  with_result_file(out / "stability.json", [&](const json& stability) { stability_section(html, out, stability), any = true; });
  if (!any) html << "<p>No results in this folder yet.</p>\n";
  html << "</body></html>\n";
  return html.str();
}

fs::path write_report(const fs::path& out) {
  const std::string html = report_html(out);
  const fs::path file = out / "report.html";
  write_stream_atomically(file, [&](std::ostream& stream) { stream << html; });
  return file;
}

}  // namespace splat::cli
