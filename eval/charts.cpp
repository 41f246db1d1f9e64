#include "charts.hpp"

#include <cstdlib>
#include <fstream>
#include <sys/wait.h>

#include "splat/core/error.hpp"

namespace splat::cli {

namespace {

namespace fs = std::filesystem;

// gnuplot and the shell both see this; single quotes stop the shell from reading anything.
std::string shell_quoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// One data block per method, in results.json's order, blocks separated by two blank lines so
// the script selects them with `index`.
void write_history(const nlohmann::json& methods, const fs::path& file) {
  std::ofstream out(file);
  out << "# seconds iteration test_psnr test_ssim; one block per method\n";
  for (const auto& m : methods) {
    out << "# " << m.at("method").get<std::string>() << "\n";
    for (const auto& h : m.at("history"))
      out << h.at("seconds").get<double>() << " " << h.at("iteration").get<int>() << " "
          << h.at("test_psnr").get<double>() << " " << h.at("test_ssim").get<double>() << "\n";
    out << "\n\n";
  }
  if (!out) throw InputError(file, "cannot write the file");
}

// Each chart goes to a temporary name first and is renamed once gnuplot succeeded.
std::string chart_script(const nlohmann::json& methods) {
  std::string plot;
  auto plot_command = [&](int column) {
    std::string command = "plot ";
    for (std::size_t i = 0; i < methods.size(); ++i) {
      const std::string name = methods[i].at("method");
      command += (i ? ", " : "") + std::string("'history.dat' index ") + std::to_string(i) +
                 " using 1:" + std::to_string(column) + " with linespoints lw 2 title '" +
                 (name == "nerf" ? "NeRF" : name) + "'";
    }
    return command + "\n";
  };
  const struct {
    const char *name, *title, *ylabel;
    int column;
  } charts[] = {{"psnr_vs_time", "Test PSNR over training time", "test PSNR (dB)", 3},
                {"ssim_vs_time", "Test SSIM over training time", "test SSIM", 4}};
  std::string script = "set xlabel 'training time (s)'\nset grid\nset key below\n";
  for (const auto& c : charts) {
    script += std::string("set title '") + c.title + "'\nset ylabel '" + c.ylabel + "'\n";
    script += std::string("set terminal pngcairo size 900,540\nset output '") + c.name + ".tmp.png'\n";
    script += plot_command(c.column);
    script += std::string("set terminal svg size 900,540\nset output '") + c.name + ".tmp.svg'\nreplot\n";
    script += "unset output\n";
  }
  return script;
}

}  // namespace

std::vector<std::string> write_charts(const nlohmann::json& methods, const fs::path& dir) {
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) return {};
  fs::create_directories(dir);
  write_history(methods, dir / "history.dat");
  {
    std::ofstream out(dir / "charts.gp");
    out << chart_script(methods);
    if (!out) throw InputError(dir / "charts.gp", "cannot write the file");
  }
  const std::string command = "cd " + shell_quoted(dir.string()) + " && gnuplot charts.gp > gnuplot.log 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw Error("gnuplot failed drawing the charts; its messages are in " + (dir / "gnuplot.log").string());
  fs::remove(dir / "gnuplot.log");
  std::vector<std::string> written;
  for (const char* name : {"psnr_vs_time", "ssim_vs_time"})
    for (const char* ext : {".png", ".svg"}) {
      const std::string final_name = std::string(name) + ext;
      fs::rename(dir / (std::string(name) + ".tmp" + ext), dir / final_name);
      written.push_back(final_name);
    }
  return written;
}

}  // namespace splat::cli
