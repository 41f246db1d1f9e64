// splat-convert IN OUT [--spz-sh-bits B1,BR]: a Gaussian model from one file format to
// another (.ply, .splat, .spz; docs/DESIGN.md §4.12), for web viewers and sharing.
#include <cstdio>
#include <filesystem>
#include <string>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/error.hpp"
#include "splat/core/file_bytes.hpp"
#include "splat/gaussians/model_file.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kUsage = R"(usage: splat-convert IN OUT [--spz-sh-bits B1,BR]

Converts a Gaussian model between formats, chosen by each file's extension:
  .ply     the 3DGS PLY the trainer writes (lossless, every SH band)
  .splat   the web viewers' 32 bytes per Gaussian (DC colour only: the higher SH bands,
           the view-dependent colour, are dropped)
  .spz     Niantic's compressed format (about a tenth of the PLY; quantised, all bands)
docs/DESIGN.md §4.12 lists every field and its quantisation.

  --spz-sh-bits B1,BR  bits kept of each .spz SH coefficient of band 1 and of bands 2-3,
                       1..8 each (default 6,6; Niantic's 5,4 is smaller and about 5 dB
                       less exact on real captures; 8,8 is the most exact)
)";

std::string size_text(std::uint64_t bytes) {
  char text[32];
  if (bytes < 1000000) std::snprintf(text, sizeof(text), "%.1f kB", double(bytes) / 1e3);
  else std::snprintf(text, sizeof(text), "%.2f MB", double(bytes) / 1e6);
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"spz-sh-bits"}, {"help"});
    if (args.has("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (args.positionals().size() != 2) throw splat::ArgumentError("expected IN and OUT model files (see --help)");
    const fs::path in = args.positionals()[0], out = args.positionals()[1];
    if (!splat::is_gaussian_model_extension(out.extension().string()))
      throw splat::ArgumentError(out.string() + ": the output's extension must name a model format (" +
                                 std::string(splat::kGaussianModelExtensions) + ")");
    std::error_code ec;
    if (fs::exists(out, ec) && fs::equivalent(in, out, ec))
      throw splat::ArgumentError(out.string() + ": the output is the input file");
    splat::SpzWriteOptions spz;
    if (auto bits = args.integer_list("spz-sh-bits", {1, 8}, 2)) {
      spz.sh1_bits = int((*bits)[0]);
      spz.sh_rest_bits = int((*bits)[1]);
    }

    const splat::GaussianModel model = splat::read_gaussian_model(in);
    splat::write_gaussian_model(model, out, spz);
    std::printf("%s (%s, %zu Gaussians, SH degree %d) -> %s (%s)\n", in.string().c_str(),
                size_text(splat::regular_file_size(in)).c_str(), model.size(), model.sh_degree,
                out.string().c_str(), size_text(splat::regular_file_size(out)).c_str());
    if (out.extension() == ".splat" && model.sh_degree > 0) {
      const std::string bands = model.sh_degree == 1 ? "band 1" : "bands 1-" + std::to_string(model.sh_degree);
      std::printf("note: .splat keeps the DC colour only; the SH %s (view-dependent colour) were dropped\n",
                  bands.c_str());
    }
    return 0;
  });
}
