#include <unistd.h>

#include <array>
#include <fstream>

#include "visfield/select/calibration.hpp"

namespace vf {
namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string model = line.substr(colon + 1);
    const std::size_t first = model.find_first_not_of(" \t");
    return first == std::string::npos ? "unknown" : model.substr(first);
  }
  return "unknown";
}

std::string host_name() {
  std::array<char, 256> buffer{};
  if (gethostname(buffer.data(), buffer.size() - 1) != 0) return "unknown";
  return buffer.data();
}

}  // namespace

MachineInfo this_machine(int threads) { return MachineInfo{host_name(), threads, cpu_model()}; }

}  // namespace vf
