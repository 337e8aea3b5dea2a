// Fuzz target: the calibration file reader. Any input must give a Calibration or a vf::Error.

#include <cstdint>
#include <string>

#include "visfield/core/error.hpp"
#include "visfield/select/calibration.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    vf::calibration_from_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
  } catch (const vf::Error&) {
  }
  return 0;
}
