#pragma once
// When a training run first reached each level of test quality, read off its scores.
//
// A run is scored only now and then (every --test-every iterations, or at the end), so the
// moment a level was crossed is known only to lie between two scores: after the last score
// below it and at (or before) the first score at or above it. Both ends are given, so a
// sparse schedule of scores shows as a wide interval rather than as a late arrival.
#include <vector>

namespace splat {

// One test score of a run: its iteration, the training seconds spent by then, its PSNR.
struct ScorePoint {
  int iteration = 0;
  double seconds = 0;
  double psnr = 0;
};

struct QualityLevel {
  double psnr = 0;             // the level, in dB
  int iteration = 0;           // of the first score at or above it
  double seconds = 0;          // training seconds at that score: the level was reached by then
  double after_seconds = 0;    // training seconds at the score before it: the level was not
                               // yet reached then
};

// Every whole dB above the first score, up to the best score, each with the first score that
// reached it (the first score's own level says only "by then", so it is not listed). `scores`
// in the order of the run (iterations increasing); the levels stop at a non-finite score.
std::vector<QualityLevel> quality_levels(const std::vector<ScorePoint>& scores);

}  // namespace splat
