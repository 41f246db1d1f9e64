#include "splat/core/ply_header.hpp"

#include <array>
#include <charconv>
#include <utility>

#include "splat/core/error.hpp"
#include "splat/core/ply_ascii.hpp"

namespace splat::ply {
namespace {

struct TypeName {
  std::string_view name;
  ScalarType type;
};

// Both spellings the PLY world uses: the original short names and the sized aliases.
constexpr std::array<TypeName, 16> kTypeNames{{
    {"char", ScalarType::kInt8},       {"int8", ScalarType::kInt8},
    {"uchar", ScalarType::kUint8},     {"uint8", ScalarType::kUint8},
    {"short", ScalarType::kInt16},     {"int16", ScalarType::kInt16},
    {"ushort", ScalarType::kUint16},   {"uint16", ScalarType::kUint16},
    {"int", ScalarType::kInt32},       {"int32", ScalarType::kInt32},
    {"uint", ScalarType::kUint32},     {"uint32", ScalarType::kUint32},
    {"float", ScalarType::kFloat32},   {"float32", ScalarType::kFloat32},
    {"double", ScalarType::kFloat64},  {"float64", ScalarType::kFloat64},
}};

// Header lines quoted in messages are cut to this length and stripped of control bytes, so a
// binary file mistaken for a header cannot flood the terminal.
constexpr std::size_t kQuotedLineChars = 60;

std::string quoted(std::string_view line) {
  std::string out = "'";
  for (std::size_t i = 0; i < line.size() && i < kQuotedLineChars; ++i) {
    const unsigned char c = static_cast<unsigned char>(line[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (line.size() > kQuotedLineChars) out += "...";
  return out + "'";
}

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

bool parse_type(std::string_view word, ScalarType& type) {
  for (const TypeName& t : kTypeNames) {
    if (t.name == word) {
      type = t.type;
      return true;
    }
  }
  return false;
}

// Accumulates the header while it is read; one method per header keyword.
class HeaderParser {
 public:
  explicit HeaderParser(const std::filesystem::path& file) : file_(file) {}

  void line(std::size_t line_number, std::string_view text,
            const std::vector<std::string_view>& words) {
    line_number_ = line_number;
    text_ = text;
    if (words.empty()) return;  // tolerated: some writers leave blank lines
    const std::string_view keyword = words[0];
    if (keyword == "comment" || keyword == "obj_info") return;
    if (keyword == "format") return format(words);
    if (keyword == "element") return element(words);
    if (keyword == "property") return property(words);
    fail("unknown header keyword");
  }

  Header finish(std::size_t data_offset) {
    if (!have_format_) throw InputError(file_, "PLY header has no 'format' line");
    for (Element& e : header_.elements) assign_offsets(e);
    header_.data_offset = data_offset;
    return std::move(header_);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(file_, "malformed PLY header line " + std::to_string(line_number_) + " " +
                                quoted(text_) + ": " + why);
  }

  void format(const std::vector<std::string_view>& words) {
    if (have_format_) fail("a second 'format' line");
    if (words.size() != 3)
      fail("expected 'format <ascii|binary_little_endian|binary_big_endian> 1.0'");
    if (words[1] == "ascii") {
      header_.format = Format::kAscii;
    } else if (words[1] == "binary_little_endian") {
      header_.format = Format::kBinaryLittleEndian;
    } else if (words[1] == "binary_big_endian") {
      header_.format = Format::kBinaryBigEndian;
    } else {
      throw InputError(file_, "unknown PLY format " + quoted(words[1]) +
                                  " (expected ascii, binary_little_endian or binary_big_endian)");
    }
    have_format_ = true;
  }

  void element(const std::vector<std::string_view>& words) {
    if (words.size() != 3) fail("expected 'element <name> <count>'");
    Element e;
    e.name = std::string(words[1]);
    const std::string_view count = words[2];
    const auto [end, ec] = std::from_chars(count.data(), count.data() + count.size(), e.count);
    if (ec != std::errc() || end != count.data() + count.size())
      fail("element count is not a non-negative integer");
    for (const Element& other : header_.elements)
      if (other.name == e.name) fail("element '" + e.name + "' is declared twice");
    header_.elements.push_back(std::move(e));
  }

  void property(const std::vector<std::string_view>& words) {
    if (header_.elements.empty()) fail("a property before any element");
    Property p;
    if (words.size() == 5 && words[1] == "list") {
      p.is_list = true;
      if (!parse_type(words[2], p.list_count_type)) fail("unknown list count type");
      if (!parse_type(words[3], p.type)) fail("unknown list item type");
      p.name = std::string(words[4]);
    } else if (words.size() == 3) {
      if (!parse_type(words[1], p.type)) fail("unknown property type");
      p.name = std::string(words[2]);
    } else {
      fail("expected 'property <type> <name>' or 'property list <type> <type> <name>'");
    }
    Element& e = header_.elements.back();
    if (e.find(p.name) != nullptr)
      fail("property '" + p.name + "' appears twice in element '" + e.name + "'");
    e.properties.push_back(std::move(p));
  }

  static void assign_offsets(Element& e) {
    std::size_t offset = 0;
    for (Property& p : e.properties) {
      if (p.is_list) break;  // rows are variable-length from here on
      p.offset = offset;
      offset += scalar_size(p.type);
    }
  }

  const std::filesystem::path& file_;
  Header header_;
  bool have_format_ = false;
  std::size_t line_number_ = 0;
  std::string_view text_;
};

}  // namespace

std::size_t scalar_size(ScalarType type) {
  switch (type) {
    case ScalarType::kInt8:
    case ScalarType::kUint8: return 1;
    case ScalarType::kInt16:
    case ScalarType::kUint16: return 2;
    case ScalarType::kInt32:
    case ScalarType::kUint32:
    case ScalarType::kFloat32: return 4;
    case ScalarType::kFloat64: return 8;
  }
  return 0;
}

std::string_view scalar_name(ScalarType type) {
  // The first spelling in kTypeNames for each type is the classic one.
  for (const TypeName& t : kTypeNames)
    if (t.type == type) return t.name;
  return "?";
}

bool Element::has_list() const {
  for (const Property& p : properties)
    if (p.is_list) return true;
  return false;
}

std::size_t Element::row_bytes() const {
  std::size_t bytes = 0;
  for (const Property& p : properties) bytes += scalar_size(p.type);
  return bytes;
}

const Property* Element::find(std::string_view property_name) const {
  for (const Property& p : properties)
    if (p.name == property_name) return &p;
  return nullptr;
}

Header parse_header(std::string_view bytes, const std::filesystem::path& file) {
  // The magic is checked on its own first so that any non-PLY file, text or binary, gets the
  // one message that says what is wrong.
  if (!(bytes.starts_with("ply\n") || bytes.starts_with("ply\r\n")))
    throw InputError(file, "not a PLY file (it does not start with the 'ply' magic line)");

  const std::string_view window = bytes.substr(0, kMaxHeaderBytes);
  HeaderParser parser(file);
  std::size_t pos = window.find('\n') + 1;
  for (std::size_t line_number = 2;; ++line_number) {
    const std::size_t newline = window.find('\n', pos);
    if (newline == std::string_view::npos) {
      // `bytes` may already be cut to the limit by the caller, so compare with the limit.
      if (window.size() >= kMaxHeaderBytes)
        throw InputError(file, "no end_header within the first " +
                                   std::to_string(kMaxHeaderBytes / 1024) +
                                   " KiB of the PLY header");
      throw InputError(file, "PLY header has no end_header line (file truncated?)");
    }
    if (line_number > kMaxHeaderLines)
      throw InputError(file, "no end_header within the first " + std::to_string(kMaxHeaderLines) +
                                 " lines of the PLY header");
    std::string_view line = window.substr(pos, newline - pos);
    if (line.ends_with('\r')) line.remove_suffix(1);
    pos = newline + 1;
    const std::vector<std::string_view> words = split_words(line);
    if (words.size() == 1 && words[0] == "end_header") return parser.finish(pos);
    parser.line(line_number, line, words);
  }
}

void expect_binary_end(const Header& header, std::size_t last_read, std::uint64_t bytes_left,
                       const std::filesystem::path& file) {
  for (std::size_t e = last_read + 1; e < header.elements.size(); ++e) {
    const Element& element = header.elements[e];
    if (element.has_list()) return;
    const std::size_t row = element.row_bytes();
    if (row != 0 && element.count > bytes_left / row)
      throw InputError(file, "truncated: the data ends inside element '" + element.name + "'");
    bytes_left -= element.count * row;
  }
  if (bytes_left != 0)
    throw InputError(file, std::to_string(bytes_left) + " bytes follow the end of the last element's data");
}

void expect_ascii_end(const Header& header, std::size_t last_read, LineCursor& cursor,
                      const std::filesystem::path& file) {
  std::string_view line;
  for (std::size_t e = last_read + 1; e < header.elements.size(); ++e)
    for (std::uint64_t r = 0; r < header.elements[e].count; ++r)
      if (!cursor.next(line))
        throw InputError(file, "ASCII data is truncated: it ends inside element '" + header.elements[e].name + "'");
  if (cursor.next(line))
    throw InputError(file, "text follows the last element's rows: '" + std::string(line.substr(0, 40)) + "'");
}

}  // namespace splat::ply
