#pragma once
// Runs a command's body and turns any error into "error: ..." on stderr and exit status 2
// (docs/DESIGN.md, "Errors").
#include <functional>

namespace splat::cli {

int run_main(const std::function<int()>& body);

}  // namespace splat::cli
