#pragma once
// Small helpers the picture and animation writers share: XML escaping, short locale-independent
// numbers, and a checked whole-file write that never leaves a half file under the final name.
#include <string>
#include <string_view>

namespace flexmb::io {

// XML 1.0 text: & < > " ' escaped; line breaks and tabs become blanks, other control characters '?'.
std::string xmlEscape(std::string_view s);
// Shortest round-trip form of v with at most `digits` significant digits ("0.5", "1e-07", "12");
// non-finite values give "0" (callers check finiteness where it matters).
std::string shortNumber(double v, int digits = 6);
// Writes text to path through path + ".part" and a rename; throws std::runtime_error naming the
// path and the reason on any failure (and removes the partial file).
void writeTextFile(const std::string& path, std::string_view text);

}  // namespace flexmb::io
