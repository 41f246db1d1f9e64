#include "splat/train/resolution_schedule.hpp"

#include <gtest/gtest.h>

#include "splat/core/error.hpp"
#include "splat/data/orbit_cameras.hpp"
#include "splat/train/splat_trainer.hpp"

#include <cmath>
#include <numbers>
#include <vector>

namespace splat {
namespace {

// A grey image: level + amplitude·cos(2π x / period_x), constant along y.
Image cosine_image(int width, int height, double period_x, float level, float amplitude) {
  Image image(width, height, 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 3; ++c)
        image.at(x, y, c) = level + amplitude * float(std::cos(2 * std::numbers::pi * x / period_x));
  return image;
}

double share_at(const SpectrumProfile& profile, double scale) {
  return profile.share[std::size_t(std::lround((scale - 1.0) * SpectrumProfile::kStepsPerUnit))];
}

TEST(ResolutionSchedule, HalvingShapeHalvesTheDivisorAtEqualSteps) {
  const ResolutionSchedule schedule({ResolutionShape::kHalving, 4, 1000}, {});
  EXPECT_EQ(schedule.divisor(1), 4);
  EXPECT_EQ(schedule.divisor(500), 4);
  EXPECT_EQ(schedule.divisor(501), 2);
  EXPECT_EQ(schedule.divisor(1000), 2);
  EXPECT_EQ(schedule.divisor(1001), 1);
  EXPECT_EQ(ResolutionSchedule({ResolutionShape::kHalving, 1, 1000}, {}).divisor(1), 1);
  EXPECT_EQ(ResolutionSchedule().divisor(1), 1);
}

TEST(ResolutionSchedule, ProfileOfAFlatImageIsAllKept) {
  const SpectrumProfile profile = spectrum_profile(cosine_image(32, 24, 8.0, 0.5f, 0.0f));
  for (double share : profile.share) EXPECT_NEAR(share, 1.0, 1e-12);
}

TEST(ResolutionSchedule, ProfileLosesAFrequencyWhereTheReducedImageCannotHoldIt) {
  // A cosine of period 8 px in 64 columns: frequency 8 of 64, kept while the reduced image
  // still has more than two pixels per period, at scales below 64 / (2·8) = 4. Its Fourier
  // magnitude is amplitude·N/2 at ±8 (two bins), the level's is level·N at DC.
  const float level = 0.5f, amplitude = 0.25f;
  const SpectrumProfile profile = spectrum_profile(cosine_image(64, 16, 8.0, level, amplitude));
  const double dc = level, wave = amplitude;  // per pixel: DC level·N, the two bins 2·amplitude·N/2
  const double kept_all = 1.0, kept_dc = dc / (dc + wave);
  EXPECT_NEAR(share_at(profile, 1.0), kept_all, 1e-6);  // float pixels leak ~1e-8
  EXPECT_NEAR(share_at(profile, 3.9375), kept_all, 1e-6);  // float pixels leak ~1e-8
  EXPECT_NEAR(share_at(profile, 4.0), kept_dc, 1e-6);  // float pixels leak ~1e-8
  EXPECT_NEAR(share_at(profile, 8.0), kept_dc, 1e-6);  // float pixels leak ~1e-8
}

TEST(ResolutionSchedule, SpectrumShapeStartsWhereAQuarterIsKeptAndEndsAtFullSize) {
  // DC holds a fifth of the magnitude (level 0.1 against amplitude 0.4): a quarter is kept
  // only below scale 4, where the wave of period 8 is lost.
  const Image image = cosine_image(64, 16, 8.0, 0.1f, 0.4f);
  const std::vector<const Image*> images{&image};
  const ResolutionSchedule schedule({ResolutionShape::kSpectrum, 8, 1000}, images);
  EXPECT_EQ(schedule.start_divisor(), 3);  // scale 3.9375, rounded down
  int previous = schedule.divisor(0);
  for (int iteration = 0; iteration <= 1000; iteration += 10) {
    const int divisor = schedule.divisor(iteration);
    EXPECT_LE(divisor, previous) << "the size never shrinks, iteration " << iteration;
    previous = divisor;
  }
  EXPECT_EQ(schedule.divisor(1000), 2) << "half size until the end of the warm-up";
  EXPECT_EQ(schedule.divisor(1001), 1);
  // steps() lists exactly the changes.
  const std::vector<std::pair<int, int>> steps = schedule.steps();
  ASSERT_GE(steps.size(), 2u);
  EXPECT_EQ(steps.front(), std::make_pair(0, 3));
  EXPECT_EQ(steps.back().second, 1);
  for (std::size_t i = 1; i < steps.size(); ++i) {
    EXPECT_EQ(schedule.divisor(steps[i].first), steps[i].second);
    EXPECT_EQ(schedule.divisor(steps[i].first - 1), steps[i - 1].second);
  }
  // An image keeping a quarter of its spectrum only above half size starts at full size,
  // and the half-size hold does not shrink it.
  const Image fine = cosine_image(64, 16, 2.5, 0.05f, 0.4f);
  const std::vector<const Image*> fine_images{&fine};
  const ResolutionSchedule full({ResolutionShape::kSpectrum, 8, 1000}, fine_images);
  EXPECT_EQ(full.start_divisor(), 1);
  EXPECT_EQ(full.divisor(500), 1);
  // The cap: never below 1/max_divisor.
  EXPECT_EQ(ResolutionSchedule({ResolutionShape::kSpectrum, 2, 1000}, images).start_divisor(), 2);
  // An image whose energy is all at low frequency starts at the cap.
  const Image flat = cosine_image(64, 16, 8.0, 0.5f, 0.0f);
  const std::vector<const Image*> flat_images{&flat};
  EXPECT_EQ(ResolutionSchedule({ResolutionShape::kSpectrum, 8, 1000}, flat_images).start_divisor(), 8);
}

TEST(ResolutionSchedule, SpectrumShapeNeedsImages) {
  EXPECT_THROW(ResolutionSchedule({ResolutionShape::kSpectrum, 4, 1000}, {}), ArgumentError);
}

// Eight orbit views of a flat grey image of the given size.
Dataset flat_orbit(int width, int height) {
  OrbitRig rig;
  rig.count = 8;
  rig.width = width;
  rig.height = height;
  Dataset dataset;
  for (const Camera& camera : orbit_cameras(rig)) {
    DatasetView view;
    view.camera = camera;
    view.image = Image(width, height, 3, 0.5f);
    dataset.train.push_back(view);
  }
  dataset.test = {dataset.train[0]};
  dataset.scene_extent = 1.1f * rig.radius;
  return dataset;
}

TEST(ResolutionSchedule, TheTrainerNeverTrainsBelow64PixelsOnTheShortSide) {
  SplatTrainingConfig config = splat_training_preset("compact");
  config.random_init_points = 200;
  config.compact.warmup_by_spectrum = true;
  config.compact.warmup_divisor = 8;
  config.compact.warmup_until = 1000;
  // A flat image keeps its whole spectrum at any size: the schedule starts at its cap.
  const Dataset large = flat_orbit(640, 512);
  EXPECT_EQ(SplatTrainer(large, config).resolution_schedule().start_divisor(), 8);
  const Dataset small = flat_orbit(192, 128);
  SplatTrainer trainer(small, config);
  EXPECT_EQ(trainer.resolution_schedule().start_divisor(), 2);
  EXPECT_EQ(trainer.step().resolution_divisor, 2);
  // The official recipe trains at full size whatever the warm-up settings say.
  config.strategy = "official";
  EXPECT_EQ(SplatTrainer(small, config).resolution_schedule().start_divisor(), 1);
}

}  // namespace
}  // namespace splat
