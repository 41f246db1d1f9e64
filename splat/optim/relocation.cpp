#include "splat/optim/relocation.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "splat/core/error.hpp"
#include "splat/core/random.hpp"

namespace splat {

namespace {

double binomial(int n, int k) {
  double c = 1.0;
  for (int j = 1; j <= k; ++j) c = c * double(n - k + j) / double(j);
  return c;
}

// Gives each source the shape of (copies of it + 1) and returns, per source row, that shape.
// `copies[i]` counts the copies made of row i.
void reshape_sources(GaussianModel& model, AdamState& adam, const std::vector<int>& copies,
                     float min_opacity) {
  for (std::size_t i = 0; i < copies.size(); ++i) {
    if (copies[i] == 0) continue;
    const int total = std::min(copies[i] + 1, kMaxRelocationCopies);
    const RelocatedShape shape = relocated_shape(model.opacity(i), total, min_opacity);
    model.opacity_logits[i] = logit(shape.opacity);
    const float log_ratio = std::log(shape.scale_ratio);
    for (int a = 0; a < 3; ++a) model.log_scales[3 * i + a] += log_ratio;
    for (GaussianModel* state : adam.rows()) state->zero_row(i);
  }
}

std::vector<int> copy_counts(const std::vector<std::size_t>& sources, std::size_t rows) {
  std::vector<int> copies(rows, 0);
  for (std::size_t s : sources) {
    if (s >= rows) throw ArgumentError("relocation: source row " + std::to_string(s) + " out of range");
    ++copies[s];
  }
  return copies;
}

}  // namespace

RelocatedShape relocated_shape(float opacity, int copies, float min_opacity) {
  if (copies < 1 || copies > kMaxRelocationCopies)
    throw ArgumentError("relocated_shape: " + std::to_string(copies) + " copies (1.." +
                        std::to_string(kMaxRelocationCopies) + ")");
  const double o = opacity;
  double o_new = 1.0 - std::pow(1.0 - o, 1.0 / copies);
  o_new = std::clamp(o_new, double(min_opacity), 1.0 - 1e-6);
  double denominator = 0.0;
  for (int i = 1; i <= copies; ++i)
    for (int k = 0; k <= i - 1; ++k)
      denominator += binomial(i - 1, k) * ((k % 2 ? -1.0 : 1.0) / std::sqrt(double(k + 1))) *
                     std::pow(o_new, k + 1);
  const double ratio = denominator > 0 ? o / denominator : 1.0;
  return {float(o_new), float(ratio)};
}

std::vector<std::size_t> sample_by_opacity(const GaussianModel& model,
                                           const std::vector<std::uint8_t>& eligible,
                                           std::size_t count, std::mt19937& rng) {
  const std::size_t n = model.size();
  std::vector<double> cumulative(n);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (eligible.empty() || eligible[i]) total += double(model.opacity(i));
    cumulative[i] = total;
  }
  std::vector<std::size_t> sources;
  if (count == 0 || !(total > 0)) return sources;
  sources.reserve(count);
  for (std::size_t d = 0; d < count; ++d) {
    const double u = double(uniform01(rng)) * total;
    // The first row whose cumulative weight exceeds u: an eligible row of non-zero weight.
    const std::size_t row = std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) -
                                        cumulative.begin());
    sources.push_back(std::min(row, n - 1));
  }
  return sources;
}

std::size_t relocate_rows(AlignedRows& rows, const std::vector<std::size_t>& targets,
                          const std::vector<std::size_t>& sources, float min_opacity) {
  if (targets.size() != sources.size())
    throw ArgumentError("relocate_rows: " + std::to_string(targets.size()) + " targets for " +
                        std::to_string(sources.size()) + " sources");
  GaussianModel& model = rows.model;
  reshape_sources(model, rows.adam, copy_counts(sources, model.size()), min_opacity);
  for (std::size_t j = 0; j < targets.size(); ++j) {
    const std::size_t t = targets[j], s = sources[j];
    model.copy_row(t, model, s);
    for (GaussianModel* state : rows.adam.rows()) state->zero_row(t);
    for (std::vector<float>* array : rows.stats) (*array)[t] = (*array)[s];
  }
  return targets.size();
}

std::size_t add_relocated_copies(AlignedRows& rows, const std::vector<std::size_t>& sources,
                                 float min_opacity) {
  reshape_sources(rows.model, rows.adam, copy_counts(sources, rows.model.size()), min_opacity);
  rows.append_copies(sources, rows.model.gather_rows(sources));
  return sources.size();
}

}  // namespace splat
