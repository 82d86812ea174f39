// libFuzzer target: the basis-file reader (io::parseBasis, io/formats/BasisFile.hpp), which reads files
// written by `flexmb reduce` and by other programs (spreadsheets, MATLAB, Python). Expected failures
// are exceptions derived from std::exception ("<file>:<line>: <reason>"). Beyond the sanitizers, every
// accepted file must round-trip: when formatBasis accepts what parseBasis returned (it refuses, e.g.,
// an empty method), parsing its output must give back the same V bit for bit and the same record;
// a difference aborts (a finding). Build and run: tools/fuzz/README.md.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>

#include "io/formats/BasisFile.hpp"

namespace {

bool sameBits(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
  for (Eigen::Index k = 0; k < a.size(); ++k)
    if (std::bit_cast<std::uint64_t>(a.data()[k]) != std::bit_cast<std::uint64_t>(b.data()[k])) return false;
  return true;
}

bool sameInfo(const flexmb::io::BasisInfo& a, const flexmb::io::BasisInfo& b) {
  return a.method == b.method && a.model == b.model && a.parameters == b.parameters && a.large == b.large &&
         sameBits(a.scaledSingularValues, b.scaledSingularValues);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  flexmb::io::BasisInfo info;
  Eigen::MatrixXd V;
  try {
    V = flexmb::io::parseBasis(text, "fuzz.csv", &info);
  } catch (const std::exception&) {
    return 0;  // rejected with a message: fine
  }
  std::string again;
  try {
    again = flexmb::io::formatBasis(V, info);
  } catch (const std::invalid_argument&) {
    return 0;  // readable but not writable as it stands (e.g. no method line): fine
  }
  flexmb::io::BasisInfo info2;
  const Eigen::MatrixXd V2 = flexmb::io::parseBasis(again, "roundtrip.csv", &info2);  // must not throw
  if (!sameBits(V, V2) || !sameInfo(info, info2)) std::abort();
  return 0;
}
