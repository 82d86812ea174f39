// libFuzzer target: the .dat reader, the model builder behind it, the kinematic check (mode 0) and
// the model picture of `flexmb show`, on arbitrary bytes. Expected failures are exceptions derived
// from std::exception (a DatError for bad input); anything else (a sanitizer report, a crash, an
// uncaught exception of another type, a hang) is a defect. Build and run: tools/fuzz/README.md.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <string_view>

#include "core/kinematics/KinematicCheck.hpp"
#include "io/formats/DatReader.hpp"
#include "io/pictures/MechanismGeometry.hpp"
#include "io/pictures/MechanismSvg.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  flexmb::core::Model model;
  try {
    model = flexmb::io::readDatString(text, "fuzz.dat");
  } catch (const std::exception&) {
    return 0;  // rejected with a message: fine
  }
  try {
    const flexmb::core::KinematicReport r = flexmb::core::checkKinematics(model);
    (void)flexmb::core::formatReport(r);
  } catch (const std::exception&) {}
  try {
    const flexmb::io::MechanismGeometry g(model);
    (void)flexmb::io::renderModelSvg(g, {});
  } catch (const std::exception&) {}
  return 0;
}
