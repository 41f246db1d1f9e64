// splat-eval result files read back by --report: results.json, sweep.json, stability.json.
#include "apps/splat-eval/report.hpp"
#include "fuzz/fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace splat;
  for (const char* name : {"results.json", "sweep.json", "stability.json"}) {
    std::filesystem::remove_all(fuzz::scratch_dir() / "report");
    std::filesystem::create_directories(fuzz::scratch_dir() / "report");
    fuzz::read_input_as((std::string("report/") + name).c_str(), data, size,
                        [](const auto& f) { cli::write_report(f.parent_path()); });
  }
  return 0;
}
