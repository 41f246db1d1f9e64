#include "common/run_main.hpp"

#include <exception>
#include <iostream>
#include <new>

namespace splat::cli {

int run_main(const std::function<int()>& body) {
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
