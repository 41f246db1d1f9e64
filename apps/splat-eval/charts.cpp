#include "apps/splat-eval/charts.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include "apps/splat-eval/result_files.hpp"
#include "splat/core/atomic_file.hpp"
#include "splat/core/error.hpp"

namespace splat::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// One curve or set of points: its legend title, gnuplot style and (x, y) rows. A row's
// optional label is drawn beside the point.
struct Series {
  std::string title, style;
  std::vector<std::pair<double, double>> points;
  std::vector<std::string> labels;
};

struct Chart {
  std::string name, title, xlabel, ylabel;
  std::string extra;  // further gnuplot settings (log scales, tics)
  std::vector<Series> series;
};

std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// A gnuplot single-quoted string: nothing inside is interpreted except '' for a quote.
std::string gp(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

void add_results_charts(const json& results, std::vector<Chart>& charts) {
  Chart psnr{"psnr_vs_time", "Test PSNR over training time", "training time (s)", "test PSNR (dB)", "", {}};
  Chart ssim{"ssim_vs_time", "Test SSIM over training time", "training time (s)", "test SSIM", "", {}};
  Chart bytes{"psnr_vs_model_bytes", "Test PSNR against model size (points over training time)",
              "model size (MB)", "test PSNR (dB)", "set logscale x\n", {}};
  Chart gaussians{"psnr_vs_gaussians", "Test PSNR against Gaussian count (points over training time)",
                  "Gaussians", "test PSNR (dB)", "set logscale x\n", {}};
  Chart render{"render_ms_vs_psnr", "Render time per test view against test PSNR (final models)",
               "test PSNR (dB)", "render time per view (ms, median)", "set logscale y\n", {}};
  for (const json& m : results.at("methods")) {
    const std::string name = method_label(m);
    Series p{name, "linespoints lw 2", {}, {}}, s = p, b = p, g = p;
    for (const json& h : m.at("history")) {
      p.points.emplace_back(h.at("seconds"), h.at("test_psnr"));
      s.points.emplace_back(h.at("seconds"), h.at("test_ssim"));
      // Older files may lack the sizes; the NeRF has no Gaussians (0).
      if (h.contains("model_bytes")) b.points.emplace_back(h.at("model_bytes").get<double>() / 1e6, h.at("test_psnr"));
      if (h.value("num_gaussians", 0.0) > 0) g.points.emplace_back(h.at("num_gaussians"), h.at("test_psnr"));
    }
    psnr.series.push_back(p);
    ssim.series.push_back(s);
    bytes.series.push_back(b);
    gaussians.series.push_back(g);
    if (m.contains("render_ms_per_view_median"))
      render.series.push_back({name, "points pt 7 ps 2", {{m.at("final").at("psnr"), m.at("render_ms_per_view_median")}}, {}});
  }
  for (Chart* c : {&psnr, &ssim, &bytes, &gaussians, &render}) charts.push_back(*c);
}

// The sweep's runs as points: (x, y) chosen by `point`, labelled with their budget.
template <class Point>
Series sweep_series(const json& sweep, const std::string& title, Point point) {
  Series s{title, "linespoints pt 5 ps 1.5 dt 2", {}, {}};
  for (const json& r : sweep.at("runs")) {
    if (!r.contains("final")) continue;
    s.points.push_back(point(r));
    s.labels.push_back(std::to_string(r.at("num_gaussians").get<long>()));
  }
  return s;
}

void add_sweep_charts(const json& sweep, std::vector<Chart>& charts) {
  const std::string title = method_label(sweep) + ", budget sweep";
  Chart chart{"sweep_psnr_vs_gaussians", "Splat test PSNR against the Gaussian budget's model",
              "Gaussians in the final model", "test PSNR (dB)", "set logscale x\n", {}};
  chart.series.push_back(sweep_series(sweep, title, [](const json& r) {
    return std::make_pair(r.at("num_gaussians").get<double>(), r.at("final").at("psnr").get<double>());
  }));
  if (sweep.contains("smallest_within")) {
    const json& r = sweep.at("runs").at(sweep.at("smallest_within").get<std::size_t>());
    chart.series.push_back({"smallest within " + sweep.at("within_db").dump() + " dB of the best", "points pt 6 ps 3 lw 2",
                            {{r.at("num_gaussians"), r.at("final").at("psnr")}}, {}});
  }
  charts.push_back(chart);
  // The sweep also belongs on the size and render-time charts, beside the comparison.
  for (Chart& c : charts) {
    if (c.name == "psnr_vs_model_bytes")
      c.series.push_back(sweep_series(sweep, title, [](const json& r) {
        return std::make_pair(r.at("model_bytes").get<double>() / 1e6, r.at("final").at("psnr").get<double>());
      }));
    if (c.name == "psnr_vs_gaussians")
      c.series.push_back(sweep_series(sweep, title, [](const json& r) {
        return std::make_pair(r.at("num_gaussians").get<double>(), r.at("final").at("psnr").get<double>());
      }));
    if (c.name == "render_ms_vs_psnr")
      c.series.push_back(sweep_series(sweep, title, [](const json& r) {
        return std::make_pair(r.at("final").at("psnr").get<double>(), r.at("render_ms_per_view_median").get<double>());
      }));
  }
}

void add_stability_chart(const json& stability, std::vector<Chart>& charts) {
  // The offsets leave 1 dB above and below the points, so that a floor line at the top or
  // the bottom of the data clears the frame.
  Chart chart{"stability_psnr", "Test PSNR under each condition (diverged runs plotted at 0)", "",
              "test PSNR (dB)", "set xtics rotate by -30\nset offsets 0.5, 0.5, 1, 1\n", {}};
  std::string tics;
  std::vector<Series> per_method;  // in the order the runs name them
  int x = 0;
  for (const json& c : stability.at("conditions")) {
    if (!c.contains("runs")) continue;
    // Tic labels are format strings to gnuplot: a literal % is written %%.
    std::string label;
    for (char ch : c.at("name").get<std::string>()) label += ch == '%' ? std::string("%%") : std::string(1, ch);
    tics += (tics.empty() ? "" : ", ") + gp(label) + " " + std::to_string(x);
    for (const json& r : c.at("runs")) {
      const std::string name = method_label(r);
      auto series = std::find_if(per_method.begin(), per_method.end(), [&](const Series& s) { return s.title == name; });
      if (series == per_method.end()) {
        static const char* const kPointTypes[] = {"7", "5", "9", "11", "13"};
        per_method.push_back({name, std::string("linespoints pt ") + kPointTypes[per_method.size() % 5] + " ps 1.5", {}, {}});
        series = per_method.end() - 1;
      }
      series->points.emplace_back(x, r.contains("final") ? r.at("final").at("psnr").get<double>() : 0.0);
      series->labels.push_back(r.at("verdict"));
    }
    ++x;
  }
  chart.extra += "set xtics (" + tics + ")\n";
  chart.series = per_method;
  if (x > 0 && stability.contains("collapse_psnr")) {
    const double line = stability.at("collapse_psnr");
    chart.series.push_back({"collapsed at or below (the background alone + margin)", "lines dt 2 lc 'grey'",
                            {{-0.25, line}, {x - 0.75, line}}, {}});
  }
  if (x > 0 && stability.contains("failure_psnr")) {
    const double line = stability.at("failure_psnr");
    chart.series.push_back({"failed below (the absolute floor)", "lines dt 3 lc 'red'",
                            {{-0.25, line}, {x - 0.75, line}}, {}});
  }
  charts.push_back(chart);
}

// A run's test PSNR at each of its test points, against its training time.
Series psnr_curve(const std::string& title, const std::string& style, const json& run) {
  Series curve{title, style, {}, {}};
  for (const json& h : run.value("history", json::array()))
    if (h.contains("test_psnr")) curve.points.emplace_back(h.at("seconds"), h.at("test_psnr"));
  return curve;
}

// Every stability run's test PSNR against its training time, one series per condition and
// method: where a curve turns down, the run was better earlier than at its end.
void add_stability_curves(const json& stability, std::vector<Chart>& charts) {
  Chart chart{"stability_curves", "Test PSNR over training time under each condition", "training time (s)",
              "test PSNR (dB)", "set key outside right\n", {}};
  for (const json& c : stability.at("conditions"))
    for (const json& r : c.value("runs", json::array())) {
      chart.series.push_back(psnr_curve(c.at("name").get<std::string>() + " / " + method_label(r), "linespoints", r));
    }
  charts.push_back(chart);
}

// A real capture's baseline runs alone, one curve per method: does training hold its best on
// photographs.
void add_real_capture_curves(const json& stability, std::vector<Chart>& charts) {
  if (!stability.value("real_capture", false)) return;
  Chart chart{"stability_real_capture", "Real capture: test PSNR over training time, every method",
              "training time (s)", "test PSNR (dB)", "", {}};
  for (const json& c : stability.at("conditions"))
    if (c.at("kind") == "baseline")
      for (const json& r : c.value("runs", json::array())) {
        chart.series.push_back(psnr_curve(method_label(r), "linespoints lw 2", r));
      }
  charts.push_back(chart);
}

void write_data(const Chart& chart, const fs::path& file) {
  write_stream_atomically(file, [&](std::ostream& out) {
    out << "# " << chart.title << "; one block per series: x y label\n";
    for (const Series& s : chart.series) {
      out << "# " << s.title << "\n";
      for (std::size_t i = 0; i < s.points.size(); ++i)
        out << s.points[i].first << " " << s.points[i].second << " \""
            << (i < s.labels.size() ? s.labels[i] : "") << "\"\n";
      out << "\n\n";
    }
  });
}

// Each chart goes to a temporary name first and is renamed once gnuplot succeeded.
std::string chart_script(const std::vector<Chart>& charts) {
  std::string script;
  for (const Chart& c : charts) {
    script += "reset\nset grid\nset key below\nset title " + gp(c.title) + "\nset xlabel " + gp(c.xlabel) +
              "\nset ylabel " + gp(c.ylabel) + "\n" + c.extra;
    std::string plot = "plot ";
    for (std::size_t i = 0; i < c.series.size(); ++i) {
      const std::string block = "'" + c.name + ".dat' index " + std::to_string(i);
      plot += (i ? ", " : "") + block + " using 1:2 with " + c.series[i].style + " title " + gp(c.series[i].title);
      if (!c.series[i].labels.empty())
        // Alternate series label above and below their points, so coinciding points stay legible.
        plot += ", " + block + " using 1:2:3 with labels offset 0," + (i % 2 ? "-1" : "1") + " font ',9' notitle";
    }
    script += "set terminal pngcairo size 900,540\nset output '" + c.name + ".tmp.png'\n" + plot + "\n";
    script += "set terminal svg size 900,540\nset output '" + c.name + ".tmp.svg'\nreplot\nunset output\n";
  }
  return script;
}

}  // namespace

ChartsDrawn write_charts(const fs::path& out) {
  std::vector<Chart> charts;
  bool any_result_file = false;
  with_result_file(out / "results.json", [&](const json& results) {
    add_results_charts(results, charts);
    any_result_file = true;
  });
  with_result_file(out / "sweep.json", [&](const json& sweep) {
    add_sweep_charts(sweep, charts);
    any_result_file = true;
  });
  with_result_file(out / "stability.json", [&](const json& stability) {
    add_stability_chart(stability, charts);
    add_stability_curves(stability, charts);
    add_real_capture_curves(stability, charts);
    any_result_file = true;
  });
  if (!any_result_file)
    throw InputError(out, "holds no results.json, sweep.json or stability.json: nothing to report (--report "
                          "redraws the charts and report of a finished splat-eval run)");
  // gnuplot refuses a plot of nothing: no empty series (a NeRF on the Gaussians chart), and no
  // chart without a series (an older file without the figures).
  for (Chart& c : charts)
    std::erase_if(c.series, [](const Series& s) { return s.points.empty(); });
  std::erase_if(charts, [](const Chart& c) { return c.series.empty(); });
  // Nothing to chart (a stability run too short to score): the report shows the tables alone.
  if (charts.empty()) return {};
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) return {.images = {}, .gnuplot_missing = true};

  const fs::path dir = out / "charts";
  fs::create_directories(dir);
  for (const Chart& c : charts) write_data(c, dir / (c.name + ".dat"));
  write_stream_atomically(dir / "charts.gp", [&](std::ostream& script) { script << chart_script(charts); });
  const std::string command = "cd " + shell_quoted(dir.string()) + " && gnuplot charts.gp > gnuplot.log 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    // No half-drawn chart stays behind under its temporary name.
    for (const Chart& c : charts)
      for (const char* ext : {".png", ".svg"}) fs::remove(dir / (c.name + ".tmp" + ext));
    throw Error("gnuplot failed drawing the charts; its messages are in " + (dir / "gnuplot.log").string());
  }
  fs::remove(dir / "gnuplot.log");
  std::vector<std::string> written;
  for (const Chart& c : charts)
    for (const char* ext : {".png", ".svg"}) {
      fs::rename(dir / (c.name + ".tmp" + ext), dir / (c.name + ext));
      written.push_back("charts/" + c.name + ext);
    }
  return {.images = written};
}

}  // namespace splat::cli
