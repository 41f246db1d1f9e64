#pragma once
// Frames of a video for structure from motion: evenly spread over its length, and in each
// stretch the sharpest of several candidates (motion blur ruins feature matching).
#include <filesystem>

#include "splat/core/image.hpp"

namespace splat::process {

struct VideoFrameOptions {
  std::filesystem::path video;
  int frames = 100;      // how many to keep
  int candidates_per_frame = 3;
  int max_side = 1600;   // longest side of the frames written (0: the video's size)
  std::filesystem::path work_dir;    // candidates and ffmpeg.log
  std::filesystem::path images_dir;  // where the kept frames go (frame_0000.png, ...)
};

// Runs ffprobe (the duration) and ffmpeg (candidates at frames × candidates_per_frame evenly
// spaced times, scaled on the way out), keeps the sharpest candidate (largest variance of
// the luminance's Laplacian) of each of `frames` equal stretches, and returns how many it
// wrote (fewer when the video has fewer frames). InputError naming the video when ffmpeg
// cannot read it or finds no frames.
int extract_sharp_frames(const VideoFrameOptions& options);

// The variance of the 4-neighbour Laplacian of the image's luminance: larger is sharper.
double sharpness(const Image& image);

}  // namespace splat::process
