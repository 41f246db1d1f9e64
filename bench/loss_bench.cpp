// splat-loss-bench: time of the training loss (L1 + SSIM), forward alone and forward+backward,
// on a pair of random images. Prints one JSON line with the medians over --repeats calls
// after a warm-up (the machine is shared, so medians, with the minimum for reference).
//   build/bin/splat-loss-bench [--width 400] [--height 400] [--threads N] [--repeats 200]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <random>
#include <vector>

#include <tbb/global_control.h>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/error.hpp"
#include "splat/optim/photometric_loss.hpp"

namespace {

constexpr int kWarmUpCalls = 10;

splat::Image random_image(int width, int height, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  splat::Image image(width, height, 3);
  for (float& v : image.data) v = uniform(rng);
  return image;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"width", "height", "threads", "repeats"}, {"help"});
    if (args.has("help")) {
      std::puts("usage: splat-loss-bench [--width W] [--height H] [--threads N] [--repeats N]");
      return 0;
    }
    const int width = args.integer("width", splat::cli::kImageSideRange).value_or(400);
    const int height = args.integer("height", splat::cli::kImageSideRange).value_or(400);
    const int repeats = args.integer("repeats", {1, 1000000}).value_or(200);
    const int threads = args.integer("threads", splat::cli::kThreadsRange).value_or(0);  // 0: oneTBB's default
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
      limit = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, threads);

    const splat::Image rendered = random_image(width, height, 1);
    const splat::Image target = random_image(width, height, 2);
    splat::SsimScratch scratch;
    splat::Image v_rendered;
    using Clock = std::chrono::steady_clock;
    std::vector<double> forward_backward_ms, forward_ms;
    for (int i = 0; i < kWarmUpCalls + repeats; ++i) {
      const auto t0 = Clock::now();
      splat::photometric_loss(rendered, target, splat::kDefaultSsimWeight, &v_rendered, scratch);
      const auto t1 = Clock::now();
      splat::photometric_loss(rendered, target, splat::kDefaultSsimWeight, nullptr, scratch);
      const auto t2 = Clock::now();
      if (i < kWarmUpCalls) continue;
      forward_backward_ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
      forward_ms.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
    }
    std::printf(
        "{\"width\": %d, \"height\": %d, \"threads\": %d, \"repeats\": %d, "
        "\"ms_forward_backward\": %.3f, \"ms_forward_backward_min\": %.3f, "
        "\"ms_forward\": %.3f, \"ms_forward_min\": %.3f}\n",
        width, height, threads, repeats, median(forward_backward_ms),
        *std::min_element(forward_backward_ms.begin(), forward_backward_ms.end()),
        median(forward_ms), *std::min_element(forward_ms.begin(), forward_ms.end()));
    return 0;
  });
}
