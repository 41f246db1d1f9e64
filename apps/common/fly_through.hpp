#pragma once
// splat-render --path: renders a model along a camera path (an orbit or spiral framed from the
// model or the capture's cameras, or a path through the cameras) into a video through ffmpeg
// and/or numbered PNGs.
#include "apps/common/render_command.hpp"

namespace splat::cli {

// Checks ffmpeg (when a video is asked for), then reads the model and the cameras, before it
// creates anything; prints a line per frame and a summary.
int run_fly_through(const RenderCommandOptions& options);

}  // namespace splat::cli
