#include "apps/splat-viewer/panel_view.hpp"

#include <GL/gl.h>
#include <cstring>

namespace splat::viewer {

bool ViewKey::operator==(const ViewKey& o) const {
  const Camera &a = camera, &b = o.camera;
  return a.camera_from_world_rotation == b.camera_from_world_rotation &&
         a.camera_from_world_translation == b.camera_from_world_translation && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.width == b.width && a.height == b.height &&
         settings.sh_degree == o.settings.sh_degree && model_version == o.model_version &&
         std::memcmp(settings.background, o.settings.background, sizeof(settings.background)) == 0;
}

namespace {
// Coarsest first. A splat model only uses these while moving; a NeRF steps through them.
const std::vector<float> kLevels = {0.125f, 0.25f, 1.0f / 3.0f, 0.5f, 0.75f, 1.0f};
}  // namespace

PanelView::PanelView(PanelModel& model, double target_ms, std::function<void()> frame_finished)
    : model_(model), policy_(kLevels, target_ms, model.progressive()), worker_(model, std::move(frame_finished)) {
  glGenTextures(1, &texture_);
  glBindTexture(GL_TEXTURE_2D, texture_);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

PanelView::~PanelView() {
  worker_.cancel();
  glDeleteTextures(1, &texture_);
}

void PanelView::update(const ViewKey& key, bool moving) {
  if (std::optional<PanelFrame> frame = worker_.take_finished()) {
    policy_.observe(frame->scale, frame->render_ms);
    glBindTexture(GL_TEXTURE_2D, texture_);
    // Full resolution maps texel to pixel exactly (nearest); a reduced frame is stretched.
    const GLint filter = frame->scale == 1.0f ? GL_NEAREST : GL_LINEAR;
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, frame->width, frame->height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 frame->rgba.data());
    shown_ = std::move(*frame);
    shown_.rgba.clear();
    shown_.rgba.shrink_to_fit();
    shown_key_ = requested_key_;
    has_frame_ = true;
    ++frames_shown_;
    const auto now = std::chrono::steady_clock::now();
    const double interval = std::chrono::duration<double>(now - last_shown_).count();
    if (frames_shown_ > 1 && interval > 0)
      frames_per_second_ = frames_per_second_ > 0 ? 0.8 * frames_per_second_ + 0.2 / interval : 1.0 / interval;
    last_shown_ = now;
  }
  const bool stale = !shows(key);
  // A slow refinement of a view the camera has left is not worth finishing.
  if (!worker_.idle() && !(requested_key_ == key) && worker_.current().scale > policy_.next(true, 0))
    worker_.cancel();
  const bool unrefined = shown_.scale < 1.0f && forced_scale_ <= 0;
  if (!worker_.idle() || !(stale || unrefined)) return;
  float scale = forced_scale_;
  if (scale <= 0) scale = stale ? policy_.next(moving, 0.0f) : policy_.next(false, shown_.scale);
  RenderRequest request;
  request.camera = key.camera;
  request.settings = key.settings;
  request.scale = scale;
  request.id = next_id_++;
  requested_key_ = key;
  worker_.request(request);
}

}  // namespace splat::viewer
