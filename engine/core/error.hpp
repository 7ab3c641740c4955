// The user-facing error of grainflow: bad input, impossible configuration, I/O failure.
// Its message is printed as is by the CLI, so it must name the key/file/line, the value
// and what is allowed. Programming errors use assertions, not this.
#pragma once
#include <stdexcept>
#include <string>

namespace grainflow {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

}  // namespace grainflow
