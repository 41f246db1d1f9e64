#pragma once
// PNG files built byte by byte, so tests can make the kinds a writer would not (palette,
// 1-bit grey, tRNS, damaged chunks) and know each stored code exactly.
#include <zlib.h>

#include <cstdint>
#include <string>

namespace splat::test {

inline void append_big_endian(std::string& bytes, std::uint32_t value) {
  for (int k = 0; k < 4; ++k) bytes.push_back(char((value >> (24 - 8 * k)) & 0xff));
}

inline std::uint32_t png_crc(const std::string& type_and_data) {
  return std::uint32_t(::crc32(0L, reinterpret_cast<const Bytef*>(type_and_data.data()),
                               uInt(type_and_data.size())));
}

// One chunk: length, type, data, CRC over type and data.
inline std::string png_chunk(const std::string& type, const std::string& data) {
  std::string chunk;
  append_big_endian(chunk, std::uint32_t(data.size()));
  chunk += type + data;
  append_big_endian(chunk, png_crc(type + data));
  return chunk;
}

inline std::string png_ihdr(std::uint32_t width, std::uint32_t height, int bit_depth, int colour_type) {
  std::string data;
  append_big_endian(data, width);
  append_big_endian(data, height);
  data += {char(bit_depth), char(colour_type), 0, 0, 0};  // deflate, adaptive filters, no interlace
  return png_chunk("IHDR", data);
}

// Scanlines (each starting with its filter byte) compressed into one IDAT chunk.
inline std::string png_idat(const std::string& scanlines) {
  uLongf size = compressBound(uLong(scanlines.size()));
  std::string packed(size, '\0');
  compress(reinterpret_cast<Bytef*>(packed.data()), &size,
           reinterpret_cast<const Bytef*>(scanlines.data()), uLong(scanlines.size()));
  packed.resize(size);
  return png_chunk("IDAT", packed);
}

inline const std::string kPngSignature = "\x89PNG\r\n\x1a\n";

// A whole file: signature, header, the chunks between (PLTE, tRNS, ...), pixels, end.
inline std::string png_file(std::uint32_t width, std::uint32_t height, int bit_depth, int colour_type,
                            const std::string& scanlines, const std::string& middle_chunks = "") {
  return kPngSignature + png_ihdr(width, height, bit_depth, colour_type) + middle_chunks +
         png_idat(scanlines) + png_chunk("IEND", "");
}

}  // namespace splat::test
