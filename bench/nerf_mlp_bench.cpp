// splat-nerf-mlp-bench: time of the NeRF MLP on one batch, forward alone and forward +
// backward (parameter gradients only, as training runs it), for the paper's network, a
// small one (depth 4, width 128, skip at layer 2) and the NGP preset's fine network (hash
// encoding in front of one 64-wide layer), whose hash encoding is also timed alone, forward
// and its tables' VJP (every level, one after another as one thread would). Prints one JSON
// line with the medians over --repeats calls after one warm-up call, the minimum for
// reference, the GEMM rate (2 flops per layer weight per sample forward, twice that again
// backward) and the nanoseconds per sample. For the encoding it also prints the memory floor:
// the time of one read at a random place in a buffer the size of its tables, and that time
// for the 4 cache lines per level a sample in uncached cells reads.
//   build/bin/splat-nerf-mlp-bench [--samples 65536] [--threads N] [--repeats 5]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <tbb/global_control.h>

#include "apps/common/arg_parser.hpp"
#include "apps/common/run_main.hpp"
#include "splat/core/error.hpp"
#include "splat/nerf/hash_encoding.hpp"
#include "splat/nerf/nerf_mlp.hpp"
#include "splat/train/nerf_training_config.hpp"

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Timing {
  double forward_ms, forward_min_ms, forward_backward_ms, forward_backward_min_ms;
};

Timing time_network(const splat::NerfMlpConfig& config, std::size_t samples, int repeats) {
  const splat::NerfMlp mlp(config, 1);
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> positions(3 * samples), directions(3 * samples), v_sigma(samples),
      v_rgb(3 * samples);
  for (float& x : positions) x = uniform(rng);
  for (std::size_t i = 0; i < samples; ++i) {  // any unit vector will do
    directions[3 * i + 2] = 1.0f;
  }
  for (float& x : v_sigma) x = uniform(rng);
  for (float& x : v_rgb) x = uniform(rng);
  std::vector<float> sigma(samples), rgb(3 * samples), v_params(mlp.parameter_count());
  splat::NerfMlpContext context;

  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  std::vector<double> forward, forward_backward;
  for (int i = 0; i < 1 + repeats; ++i) {  // the first call sizes the context
    const auto t0 = Clock::now();
    mlp.forward(positions, directions, sigma, rgb, context);
    const auto t1 = Clock::now();
    std::fill(v_params.begin(), v_params.end(), 0.0f);
    mlp.forward(positions, directions, sigma, rgb, context);
    mlp.backward(context, v_sigma, v_rgb, v_params);
    const auto t2 = Clock::now();
    if (i == 0) continue;
    forward.push_back(ms(t0, t1));
    forward_backward.push_back(ms(t1, t2));
  }
  return {median(forward), *std::min_element(forward.begin(), forward.end()),
          median(forward_backward),
          *std::min_element(forward_backward.begin(), forward_backward.end())};
}

// The hash encoding alone on `samples` points in the unit cube: forward, and the tables' VJP.
struct EncodingTiming {
  double forward_ms, table_vjp_ms;
};

EncodingTiming time_encoding(const splat::HashEncodingSettings& settings, std::size_t samples, int repeats) {
  const splat::HashGridLayout layout(settings);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> uniform(0.0f, 1.0f);
  std::vector<float> unit(3 * samples), table(layout.parameter_count()), v_table(layout.parameter_count());
  for (float& x : unit) x = uniform(rng);
  for (float& x : table) x = 1e-4f * uniform(rng);
  std::vector<float> code(samples * std::size_t(layout.output_size()));
  using Clock = std::chrono::steady_clock;
  std::vector<double> forward, backward;
  for (int i = 0; i < 1 + repeats; ++i) {
    const auto t0 = Clock::now();
    splat::hash_encode(layout, table.data(), unit.data(), samples, code.data());
    const auto t1 = Clock::now();
    for (int level = 0; level < settings.levels; ++level)
      splat::hash_encode_vjp_table(layout, level, unit.data(), samples, code.data(), v_table.data());
    const auto t2 = Clock::now();
    if (i == 0) continue;
    forward.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    backward.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  return {median(forward), median(backward)};
}

// The memory floor under the encoding: reads of a float pair at random places in a buffer as
// large as the NGP tables, eight independent streams in flight (a level's 8 corners). A
// corner and its x neighbour share a cache line, so a sample costs about 4 such reads per
// level when its cells are not in cache.
double random_pair_read_ns(std::size_t floats, std::size_t reads) {
  std::vector<float> buffer(floats, 1.0f);
  const std::uint64_t pairs = floats / 2;
  constexpr int kStreams = 8;
  reads -= reads % kStreams;
  std::uint32_t state[kStreams];
  double sum[kStreams] = {};  // one per stream: a shared sum would chain the reads' additions
  for (int s = 0; s < kStreams; ++s) state[s] = 0x9e3779b9u * std::uint32_t(s + 1);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t r = 0; r < reads; r += kStreams)
    for (int s = 0; s < kStreams; ++s) {
      std::uint32_t x = state[s];  // xorshift32
      x ^= x << 13, x ^= x >> 17, x ^= x << 5;
      state[s] = x;
      const std::size_t pair = std::size_t((std::uint64_t(x) * pairs) >> 32);
      sum[s] += buffer[2 * pair] + buffer[2 * pair + 1];
    }
  const auto t1 = std::chrono::steady_clock::now();
  double total = 0;
  for (double x : sum) total += x;
  if (total != double(2 * reads)) throw splat::Error("random_pair_read_ns: the reads were not made");
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / double(reads);
}

std::string json(const char* name, const splat::NerfMlpConfig& config, std::size_t samples,
                 const Timing& t) {
  const double params = double(splat::NerfMlp(config).layer_parameter_count());
  const double forward_gflop = 2.0 * params * double(samples) * 1e-9;
  char buffer[512];
  std::snprintf(buffer, sizeof buffer,
                "\"%s\": {\"depth\": %d, \"width\": %d, \"parameters\": %.0f, "
                "\"ms_forward\": %.1f, \"ms_forward_min\": %.1f, \"ms_forward_backward\": %.1f, "
                "\"ms_forward_backward_min\": %.1f, \"gflops_forward\": %.1f, "
                "\"gflops_forward_backward\": %.1f, \"ns_per_sample_forward\": %.0f, "
                "\"ns_per_sample_forward_backward\": %.0f}",
                name, config.depth, config.width, params, t.forward_ms, t.forward_min_ms,
                t.forward_backward_ms, t.forward_backward_min_ms,
                forward_gflop / (t.forward_ms * 1e-3),
                3 * forward_gflop / (t.forward_backward_ms * 1e-3), t.forward_ms * 1e6 / double(samples),
                t.forward_backward_ms * 1e6 / double(samples));
  return buffer;
}

}  // namespace

int main(int argc, char** argv) {
  return splat::cli::run_main([&] {
    splat::cli::ArgParser args(argc, argv, {"samples", "threads", "repeats"}, {"help"});
    if (args.has("help")) {
      std::puts("usage: splat-nerf-mlp-bench [--samples N] [--threads N] [--repeats N]");
      return 0;
    }
    const int samples = args.integer("samples", {1, 1 << 24}).value_or(65536);
    const int repeats = args.integer("repeats", {1, 1000000}).value_or(5);
    const int threads = args.integer("threads", splat::cli::kThreadsRange).value_or(0);  // 0: oneTBB's default
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
      limit = std::make_unique<tbb::global_control>(
          tbb::global_control::max_allowed_parallelism, threads);

    const splat::NerfMlpConfig paper;
    splat::NerfMlpConfig small;
    small.depth = 4;
    small.width = 128;
    small.skip_layer = 2;
    const splat::NerfMlpConfig ngp = splat::nerf_training_preset("ngp").model.fine;
    const Timing paper_time = time_network(paper, std::size_t(samples), repeats);
    const Timing small_time = time_network(small, std::size_t(samples), repeats);
    const Timing ngp_time = time_network(ngp, std::size_t(samples), repeats);
    const EncodingTiming encoding = time_encoding(ngp.hash, std::size_t(samples), repeats);
    const splat::HashGridLayout layout(ngp.hash);
    std::vector<double> read_ns;
    for (int i = 0; i < repeats; ++i)
      read_ns.push_back(random_pair_read_ns(layout.parameter_count(), std::size_t(samples) * 64));
    const double pair_read_ns = median(read_ns);
    std::printf("{\"samples\": %d, \"threads\": %d, \"repeats\": %d, %s, %s, %s, "
                "\"ngp_encoding\": {\"ns_per_sample_forward\": %.0f, \"ns_per_sample_table_vjp\": %.0f, "
                "\"ns_per_random_pair_read\": %.2f, \"ns_per_sample_read_floor\": %.0f}}\n",
                samples, threads, repeats, json("default", paper, samples, paper_time).c_str(),
                json("small", small, samples, small_time).c_str(), json("ngp", ngp, samples, ngp_time).c_str(),
                encoding.forward_ms * 1e6 / double(samples), encoding.table_vjp_ms * 1e6 / double(samples),
                pair_read_ns, pair_read_ns * 4 * ngp.hash.levels);
    return 0;
  });
}
