#include "splat/gaussians/gzip.hpp"

#include <algorithm>
#include <climits>
#include <string>

#include <zlib.h>

#include "splat/core/error.hpp"

namespace splat {
namespace {

// zlib's windowBits for a gzip wrapper (not zlib's own, not raw deflate).
constexpr int kGzipWindowBits = 16 + MAX_WBITS;
constexpr std::size_t kChunkBytes = 1 << 16;

enum class Stop { kAtEnd, kAtCount };

// Inflates until the stream ends, or until `limit` bytes are out when `stop` is kAtCount.
// With kAtEnd, more than `limit` bytes is an error.
std::vector<unsigned char> inflate_gzip(std::span<const unsigned char> compressed, std::size_t limit, Stop stop,
                                        const std::filesystem::path& file) {
  if (compressed.size() > UINT_MAX) throw InputError(file, "the compressed data is larger than zlib reads at once");
  z_stream stream{};
  if (inflateInit2(&stream, kGzipWindowBits) != Z_OK) throw Error("zlib: cannot start inflating");
  stream.next_in = const_cast<Bytef*>(compressed.data());
  stream.avail_in = static_cast<uInt>(compressed.size());
  std::vector<unsigned char> out;
  int result = Z_OK;
  while (true) {
    // One byte past the limit tells "exactly the limit" from "more than the limit".
    const std::size_t want = std::min(kChunkBytes, limit + (stop == Stop::kAtEnd ? 1 : 0) - out.size());
    if (want == 0) break;
    const std::size_t before = out.size();
    out.resize(before + want);
    stream.next_out = out.data() + before;
    stream.avail_out = static_cast<uInt>(want);
    result = inflate(&stream, Z_NO_FLUSH);
    out.resize(out.size() - stream.avail_out);
    if (result == Z_STREAM_END) break;
    if (result != Z_OK) {
      const std::string reason = stream.msg ? stream.msg : "no further data";
      inflateEnd(&stream);
      if (result == Z_BUF_ERROR) throw InputError(file, "the gzip data ends early");
      throw InputError(file, "not valid gzip data (" + reason + ")");
    }
  }
  const bool ended = result == Z_STREAM_END;
  const uInt left_over = stream.avail_in;
  inflateEnd(&stream);
  if (stop == Stop::kAtCount) return out;
  if (!ended) {
    throw InputError(file, "inflates to more than the " + std::to_string(limit) +
                               " bytes its header allows");
  }
  if (left_over != 0) throw InputError(file, std::to_string(left_over) + " bytes follow the end of the gzip stream");
  return out;
}

}  // namespace

std::vector<unsigned char> gzip(std::span<const unsigned char> bytes) {
  z_stream stream{};
  if (deflateInit2(&stream, Z_DEFAULT_COMPRESSION, Z_DEFLATED, kGzipWindowBits, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw Error("zlib: cannot start deflating");
  std::vector<unsigned char> out(deflateBound(&stream, static_cast<uLong>(bytes.size())));
  stream.next_in = const_cast<Bytef*>(bytes.data());
  stream.avail_in = static_cast<uInt>(bytes.size());
  stream.next_out = out.data();
  stream.avail_out = static_cast<uInt>(out.size());
  const int result = deflate(&stream, Z_FINISH);
  out.resize(out.size() - stream.avail_out);
  deflateEnd(&stream);
  if (result != Z_STREAM_END) throw Error("zlib: deflate did not finish");
  return out;
}

std::vector<unsigned char> gunzip(std::span<const unsigned char> compressed, std::size_t max_bytes,
                                  const std::filesystem::path& file) {
  return inflate_gzip(compressed, max_bytes, Stop::kAtEnd, file);
}

std::vector<unsigned char> gunzip_prefix(std::span<const unsigned char> compressed, std::size_t count,
                                         const std::filesystem::path& file) {
  return inflate_gzip(compressed, count, Stop::kAtCount, file);
}

}  // namespace splat
