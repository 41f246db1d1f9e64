#pragma once
// Schedules count views: a training step over a batch of B views advances the iteration
// count by B (splat/train/view_batch.hpp), so an event due at one view number, or every so
// many views, falls in the step whose views (last − B, last] hold it. With B = 1 these are
// the plain tests `last == value` and `last % interval == 0`.
namespace splat {

// Whether a multiple of `interval` lies in (last − views, last]. Never for interval ≤ 0.
// Expects last ≥ views ≥ 1.
inline bool step_reaches_multiple(int last, int views, int interval) {
  return interval > 0 && last / interval != (last - views) / interval;
}

// Whether `value` lies in (last − views, last].
inline bool step_reaches(int last, int views, int value) { return value > last - views && value <= last; }

}  // namespace splat
