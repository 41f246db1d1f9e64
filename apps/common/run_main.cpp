#include "apps/common/run_main.hpp"

#include <csignal>
#include <exception>
#include <iostream>
#include <new>

namespace splat::cli {

int run_main(const std::function<int()>& body) {
  // Past a file-size limit (ulimit -f) the kernel would kill the process by this signal, in
  // the middle of a write; ignored, the write fails instead (EFBIG), and the writer reports it
  // naming the file, with the previous outputs left as they were.
  std::signal(SIGXFSZ, SIG_IGN);
  try {
    return body();
  } catch (const std::bad_alloc&) {
    std::cerr << "error: out of memory\n";
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
  }
  return 2;
}

}  // namespace splat::cli
