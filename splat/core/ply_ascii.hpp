#pragma once
// Reading a PLY file's ASCII data: rows line by line, values split and parsed exactly. Shared
// by the readers of Gaussian models (gaussians/ply_io) and of point clouds (data/point_cloud_ply).
#include <charconv>
#include <cstddef>
#include <string_view>
#include <system_error>
#include <vector>

namespace splat::ply {

// Walks ASCII data line by line; blank lines between rows are skipped.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text) : text_(text) {}
  bool next(std::string_view& line) {
    while (pos_ < text_.size()) {
      std::size_t end = text_.find('\n', pos_);
      if (end == std::string_view::npos) end = text_.size();
      line = text_.substr(pos_, end - pos_);
      pos_ = end + 1;
      if (line.find_first_not_of(" \t\r") != std::string_view::npos) return true;
    }
    return false;
  }
  std::size_t remaining() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
};

// Splits `line` into at most `max_words` + 1 words (one extra to detect surplus values).
inline std::size_t split_values(std::string_view line, std::vector<std::string_view>& words,
                         std::size_t max_words) {
  words.clear();
  std::size_t i = 0;
  while (i < line.size() && words.size() <= max_words) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words.size();
}

template <typename T>
inline bool parse_number(std::string_view word, T& value) {
  if (word.size() > 1 && word[0] == '+') word.remove_prefix(1);  // from_chars rejects '+'
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc() && end == word.data() + word.size();
}

}  // namespace splat::ply
