#pragma once
// Tests that are slow by design (the SLOW_TESTS of their folder's CMakeLists.txt, ctest label
// `<module>-slow`) check the same property on a shorter run when FLEXMB_SHORT_TESTS is set to anything
// but "" or "0". Sanitizer builds set it for exactly those tests (CMakeLists.txt,
// flexmb_discover_tests): under ASan + UBSan they run 10-80 times slower, and the short run goes
// through the same code, only with fewer steps or smaller sizes. Normal builds run the full versions.
// (Namespace `test`, not `testing`: after `using namespace flexmb;` gtest's `testing::` would be
// ambiguous.)
#include <cstdlib>
#include <string_view>

namespace flexmb::test {

inline bool shortRun() {
  const char* v = std::getenv("FLEXMB_SHORT_TESTS");
  return v && *v && std::string_view(v) != "0";
}

}  // namespace flexmb::test
