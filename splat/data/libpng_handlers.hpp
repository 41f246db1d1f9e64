#pragma once
// How the PNG reader and writer take libpng's reports: an error is kept (for our own message
// naming the file) and jumps back to the setjmp of the call that failed; warnings (chunks we
// do not use, say a known-incorrect sRGB profile) are dropped rather than printed. Either way
// nothing of libpng's reaches the terminal.
#include <png.h>

#include <cstdio>

namespace splat::libpng {

struct ErrorMessage {
  char text[256] = {};
};

[[noreturn]] inline void on_error(png_structp png, png_const_charp message) {
  auto* error = static_cast<ErrorMessage*>(png_get_error_ptr(png));
  std::snprintf(error->text, sizeof error->text, "%s", message);
  png_longjmp(png, 1);
}

inline void on_warning(png_structp, png_const_charp) {}

inline const char* text_of(const ErrorMessage& error) { return error.text[0] ? error.text : "unknown libpng error"; }

}  // namespace splat::libpng
